/* `nbrdf eval --model neural*`: f computed exactly the way a bake computes a
 * texel, for the same CSV contract as the ground-truth models. Parameters go
 * through the bake's own code (src/bake/bake_tuple.h): the roughness
 * convention, validation, the trained ranges under the range policy (clamp
 * with a warning, or refuse), then base-table look-up, layering network and
 * decoder. */
#ifndef NBRDF_CLI_EVAL_NEURAL_H
#define NBRDF_CLI_EVAL_NEURAL_H

#include <stddef.h>

#include "nbrdf/bake.h"
#include "nbrdf/brdf.h"

typedef enum cli_eval_neural_kind {
  CLI_EVAL_NEURAL_NONE = 0,
  CLI_EVAL_NEURAL_LAYERED,   /* alpha1, eta, alpha2, r0, albedo, sigma_t */
  CLI_EVAL_NEURAL_CONDUCTOR, /* alpha, r0 */
  CLI_EVAL_NEURAL_DIELECTRIC /* alpha, eta */
} cli_eval_neural_kind;

typedef struct cli_eval_neural_options {
  const char *bundle; /* NULL: the default bundle (cli_model_load) */
  nbrdf_roughness roughness;
  nbrdf_range_policy range;
} cli_eval_neural_options;

/* Loads the bundle and fills f[k] for n rows of parameters (n × that kind's
 * count, named by `columns`) and queries. A value the bake would clamp is
 * clamped with one warning per value on stderr naming its line (`lines[k]`)
 * in the bake's words; one the bake would refuse stops with an error naming
 * the line and column. Returns a CLI exit status. */
int cli_eval_neural(const cli_eval_neural_options *o, cli_eval_neural_kind kind, size_t n,
                    const double *params, const char *const *columns, const nbrdf_query *queries,
                    const size_t *lines, double *f);

#endif
