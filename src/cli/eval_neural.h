/* `nbrdf eval --model neural*`: f computed the way a bake computes a texel
 * (base-table look-up, layering network, decoder), for the same CSV contract
 * as the ground-truth models. */
#ifndef NBRDF_CLI_EVAL_NEURAL_H
#define NBRDF_CLI_EVAL_NEURAL_H

#include <stddef.h>

#include "nbrdf/brdf.h"

typedef enum eval_neural_kind {
  EVAL_NEURAL_NONE = 0,
  EVAL_NEURAL_LAYERED,   /* alpha1, eta, alpha2, r0, albedo, sigma_t */
  EVAL_NEURAL_CONDUCTOR, /* alpha, r0 */
  EVAL_NEURAL_DIELECTRIC /* alpha, eta */
} eval_neural_kind;

/* Loads `bundle` (NULL: models/default) and fills f[k] for n rows of
 * parameters (n × that kind's count) and queries. Parameters outside the
 * bundle's tables are clamped to them with one warning per row on stderr
 * naming its line (`lines[k]`); σT beyond the trained 5 is extrapolated by the
 * layering network and warned about the same way. Returns a CLI exit status. */
int eval_neural(const char *bundle, eval_neural_kind kind, size_t n, const double *params,
                const nbrdf_query *queries, const size_t *lines, double *f);

#endif
