/* --accuracy auto (NBRDF_BAKE_AUTO): the cheapest level whose held-out lobe
 * error meets the target. The fast level's error is measured first on the
 * held-out tuples the fitted level would use; above the target the bake
 * climbs fitted -> specialised (-> compact when compact_dim is given), each
 * at the budget, and stops at the first level that meets it and is not worse
 * than fast (bake_fit_worse_than_fast). None meeting it: the best reached is
 * baked, or with `require` the bake fails before any file exists. */
#ifndef NBRDF_BAKE_BAKE_AUTO_H
#define NBRDF_BAKE_BAKE_AUTO_H

#include "bake/bake_accuracy.h"

#define BAKE_AUTO_MAX_TRIED 4

typedef struct bake_auto_outcome {
  double max_error; /* the target, fraction */
  int tried;        /* levels tried in order, fast first */
  nbrdf_bake_accuracy level[BAKE_AUTO_MAX_TRIED];
  double error[BAKE_AUTO_MAX_TRIED]; /* each one's held-out median, fraction */
  int worse[BAKE_AUTO_MAX_TRIED];    /* worse than fast on its held-out tuples */
  int met;
  nbrdf_bake_accuracy chosen;
  double budget;           /* per level tried */
  double suggested_budget; /* !met: would likely reach the target; 0: unlikely to help */
  size_t distinct;
} bake_auto_outcome;

/* The plan/fit stage of AUTO: `r` receives the chosen level's fit (zero, level FAST,
 * when fast is chosen), `out` what was tried. Progress: stage "ground truth" and "fit" of
 * each level tried, through `ticker`. With o->require and no level meeting the target:
 * NBRDF_ERR_UNSUPPORTED with the figures. */
nbrdf_status bake_auto_choose(const nbrdf_model *model, const bake_scene *scenes, size_t n_scenes,
                              const nbrdf_bake_options *o, core_ticker *ticker, bake_fit_result *r,
                              bake_auto_outcome *out, nbrdf_error *err);

/* "chosen=specialised; maxError=5; met=1; tried=fast:11.70,fitted:6.71,specialised:2.30"
 * (percent), then "; suggestedBudget=B" when not met. */
void bake_auto_describe(const bake_auto_outcome *a, char *buf, size_t cap);

/* One line for the user: what was chosen and why, or that nothing met the target. */
void bake_auto_message(const bake_auto_outcome *a, char *buf, size_t cap);

#endif
