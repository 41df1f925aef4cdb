/* Latent interpolation (paper §3.4): BRDFs blend by averaging their latents. */
#include <math.h>

#include "core/error.h"
#include "nbrdf/model.h"

nbrdf_status nbrdf_latent_interpolate(size_t count, int dim, const float *latents,
                                      const double *weights, float *out, nbrdf_error *err) {
  if (count < 1 || dim < 1)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "interpolate: %zu latents of %d floats", count, dim);
  double sum = 0.0;
  for (size_t k = 0; k < count; k++) {
    if (!isfinite(weights[k]) || weights[k] < 0.0)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "interpolate: weight %zu = %g is not finite and >= 0", k, weights[k]);
    sum += weights[k];
  }
  if (!(sum > 0.0) || !isfinite(sum))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "interpolate: the weights sum to %g, not > 0", sum);
  for (int j = 0; j < dim; j++) {
    double acc = 0.0;
    for (size_t k = 0; k < count; k++)
      acc += weights[k] * latents[k * (size_t)dim + j];
    /* In double the result is within a few 1e-16 of the exact mean, far below half a
     * float ulp: averaging identical latents gives them back bit for bit. */
    out[j] = (float)(acc / sum);
  }
  return NBRDF_OK;
}
