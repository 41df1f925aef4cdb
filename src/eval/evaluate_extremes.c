/* The `extremes` set: named constants at the corners of the parameter space where a
 * closed form or a limit says what the BRDF must do (issue 35: a smooth coat over a mirror
 * keeps its albedo; a coat of eta near 1 is nearly absent), evaluated end to end like
 * `layer`. Fixed, not drawn: the same cases for every bundle. */
#include "eval/evaluate.h"

#include <string.h>

typedef struct extreme {
  const char *name;
  double alpha1, eta, albedo, sigma_t, alpha2, r0;
} extreme;

static const extreme cases[EVAL_EXTREMES_COUNT] = {
    {"smooth coat over a mirror", 0.01, 1.5, 1.0, 0.0, 0.01, 1.0},
    {"smooth high-IOR coat over a mirror", 0.01, 2.0, 1.0, 0.0, 0.01, 1.0},
    {"smooth low-IOR coat over a mirror", 0.01, 1.05, 1.0, 0.0, 0.01, 1.0},
    {"no coat (eta 1) over a mirror", 0.01, 1.0, 1.0, 0.0, 0.01, 1.0},
    {"smooth coat over a rough mirror", 0.01, 1.5, 1.0, 0.0, 0.5, 1.0},
    {"rough coat over a mirror", 0.5, 1.5, 1.0, 0.0, 0.01, 1.0},
    {"smooth coat over black", 0.01, 1.5, 1.0, 0.0, 0.3, 0.0},
    {"smooth coat over an absorbing slab", 0.01, 1.5, 0.0, 5.0, 0.3, 0.9},
    {"barely-there coat over a rough conductor", 0.3, 1.02, 1.0, 0.0, 0.3, 0.9},
};

const char *eval_extremes_name(int index) {
  return index >= 0 && index < EVAL_EXTREMES_COUNT ? cases[index].name : "?";
}

void eval_extremes_params(int index, train_params *p) {
  const extreme *e = &cases[index < 0 ? 0 : index % EVAL_EXTREMES_COUNT];
  memset(p, 0, sizeof *p);
  p->kind = TRAIN_LAYERED2, p->n_coats = 1;
  p->coat[0] = (train_coat){e->alpha1, e->eta, e->albedo, e->sigma_t};
  p->base_alpha = e->alpha2, p->base_r0 = e->r0;
}
