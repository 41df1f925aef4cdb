/* Base-latent tables (model/base_table.h) filled by projection: every grid node
 * is an analytic BRDF (top rough dielectric at (α1, η), bottom rough conductor
 * at (α2, R0)) whose samples come from the data-set generator; all nodes of a
 * table are projected together with the decoder frozen, from the same zero
 * latent, so neighbouring nodes land on neighbouring latents and bilinear
 * look-up between them stays meaningful (docs/TRAINING.md measures the error
 * the interpolation adds). */
#ifndef NBRDF_TRAIN_TABLE_FIT_H
#define NBRDF_TRAIN_TABLE_FIT_H

#include <signal.h>

#include "model/base_table.h"
#include "model/decoder.h"
#include "nbrdf/status.h"
#include "train/params.h"

typedef struct train_table_settings {
  int alpha_nodes; /* α = u³, u uniform in [0.216, 1] (Table 2's α), ends 0.01 and 1 */
  int eta_nodes;   /* η = eta_min + (2 − eta_min)·u^eta_warp, u uniform in [0, 1] */
  int r0_nodes;    /* R0 = u^r0_warp, u uniform in [0, 1] */
  /* 1: uniform; > 1: denser at the dim end (η near 1.05, R0 near 0), where a
   * latent changes fastest relative to the BRDF's own size. */
  double eta_warp, r0_warp;
  int steps; /* projection steps */
  uint64_t seed;
  nbrdf_progress_fn progress; /* stage "tables", done/total in steps */
  void *user;
  /* Both tables are projected in one trainer run (train/projection.h): */
  const char *checkpoint;    /* resumable state, written atomically (NULL: none) */
  double checkpoint_seconds; /* at most this long between checkpoints */
  double max_seconds;        /* stop (checkpointed) after this long; 0 = no limit */
  int64_t stop_at_step;      /* stop (checkpointed) after this step; 0 = none */
  /* First η node: 1.05 (Table 2's lower end) by default; 1 makes the bundle
   * accept η = 1 (no coat: an index-matched interface) without clamping,
   * since a bake's η range is the table's grid (bake_tuple.c). [1, 1.9]. */
  double eta_min;
  volatile sig_atomic_t *cancel; /* may be NULL; also seen between the two tables of a step */
} train_table_settings;

#define TRAIN_TABLE_SETTINGS_DEFAULT                                                               \
  { 16, 8, 9, 1.0, 1.0, 800, 1u, NULL, NULL, NULL, 300.0, 0.0, 0, 1.05, NULL }

/* Fills tables[MODEL_TABLE_DIELECTRIC] and tables[MODEL_TABLE_CONDUCTOR]
 * (initialised here; free with model_base_table_free). NBRDF_ERR_CANCELLED
 * when stopped (checkpointed when s->checkpoint is set: the same call resumes). */
nbrdf_status train_tables_fit(model_decoder *dec, const train_table_settings *s,
                              model_base_table tables[2], nbrdf_error *err);

/* Projects arbitrary BRDFs `params` into out [n × D] with the decoder frozen,
 * from a zero latent, on the data-set generator's samples with the random
 * streams of (family, index k) (generated in parallel). Analytic and layered
 * BRDFs alike: tables, held-out evaluation and the interpolation-error
 * measurement use it. */
typedef struct core_ticker core_ticker;
/* Progress of a projection (optional): each step ticks `tk` with `stage`,
 * done = done0 + step of `total`; a stop fails with NBRDF_ERR_CANCELLED. */
typedef struct train_project_progress {
  core_ticker *tk;
  const char *stage;
  double done0, total;
} train_project_progress;
/* The projection settings every projection of BRDF parameters uses. */
typedef struct train_projection train_projection;
void train_project_defaults(int steps, uint64_t seed, train_projection *p);
nbrdf_status train_project_params(model_decoder *dec, size_t n, const train_params *params,
                                  uint64_t family, int steps, uint64_t seed, float *out,
                                  const train_project_progress *progress, nbrdf_error *err);

#endif
