/* nbrdf_model_project (include/nbrdf/model.h): the public projection. It is a
 * fit, so it runs in the one trainer (train/projection.h: one set, in memory,
 * silent) rather than a loop of its own; the model layer's argument checks
 * (model/api_checks.h) are shared with the other public model calls. */
#include <math.h>

#include "core/error.h"
#include "model/api_checks.h"
#include "model/bundle.h"
#include "train/projection.h"

static nbrdf_status check_projection(size_t n_brdfs, const size_t *offsets, const float *wi,
                                     const float *wo, const float *f,
                                     const nbrdf_project_options *o, nbrdf_error *err) {
  if (n_brdfs < 1) return core_fail(err, NBRDF_ERR_ARGUMENT, "project: no BRDF given");
  if (offsets[0] != 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "project: offsets[0] = %zu, expected 0", offsets[0]);
  for (size_t b = 0; b < n_brdfs; b++)
    if (offsets[b + 1] <= offsets[b])
      return core_fail(err, NBRDF_ERR_ARGUMENT, "project: BRDF %zu has no samples", b);
  size_t rows = offsets[n_brdfs];
  nbrdf_status st = model_check_directions(rows, wi, wo, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "project: ");
    return st;
  }
  for (size_t r = 0; r < rows; r++)
    if (!(f[r] >= 0.0f) || !isfinite(f[r]))
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "project: f of sample %zu = %g is not finite and >= 0", r, f[r]);
  if (o->steps < 0 || o->rows_per_brdf < 1 || !(o->learning_rate > 0.0f) ||
      !isfinite(o->learning_rate) || (o->loss != NBRDF_LOSS_L1 && o->loss != NBRDF_LOSS_L1_LOG1P))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "project: options need steps >= 0, rows_per_brdf >= 1, a learning rate > 0 "
                     "and a known loss");
  return NBRDF_OK;
}

nbrdf_status nbrdf_model_project(const nbrdf_model *m, size_t n_brdfs, const size_t *offsets,
                                 const float *wi, const float *wo, const float *f,
                                 const nbrdf_project_options *options, float *out,
                                 double *final_loss, nbrdf_error *err) {
  nbrdf_project_options defaults = NBRDF_PROJECT_OPTIONS_DEFAULT;
  const nbrdf_project_options *o = options ? options : &defaults;
  nbrdf_status st = check_projection(n_brdfs, offsets, wi, wo, f, o, err);
  if (st != NBRDF_OK) return st;
  size_t count = n_brdfs * (size_t)m->latent_dim;
  if (o->init_from_out) {
    st = model_check_finite(out, count, "project: initial latents", err);
    if (st != NBRDF_OK) return st;
  } else {
    for (size_t k = 0; k < count; k++)
      out[k] = 0.0f;
  }
  /* Adam at the given rate, no decay; batches sized as the other public calls'
   * (model_batch_for). The decoder stays frozen (the fit never writes it), so
   * sharing a loaded model between threads is safe. */
  train_projection p = {.loss = o->loss == NBRDF_LOSS_L1 ? MODEL_LOSS_L1 : MODEL_LOSS_L1_LOG1P,
                        .rows_per_brdf = o->rows_per_brdf,
                        .lr = o->learning_rate,
                        .decay_every = 0,
                        .decay_gamma = 1.0f,
                        .seed = o->seed,
                        .steps = o->steps,
                        .max_batch = model_batch_for(n_brdfs * (size_t)o->rows_per_brdf, 1)};
  model_samples samples = {n_brdfs, offsets, wi, wo, f, NULL};
  float *const latents[1] = {out};
  st = train_project_sets(m->decoder, 1, &samples, latents, &p, NULL, NULL, err);
  if (st == NBRDF_OK && final_loss)
    st = train_projection_loss(m->decoder, &samples, out, &p, final_loss, NULL, err);
  if (st != NBRDF_OK) core_error_prefix(err, "project: ");
  return st;
}
