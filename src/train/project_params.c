#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/progress.h"
#include "model/autodecoder.h"
#include "train/dataset.h"
#include "train/samples.h"
#include "train/table_fit.h"

nbrdf_status train_project_params(model_decoder *dec, size_t n, const train_params *params,
                                  uint64_t family, int steps, uint64_t seed, float *out,
                                  const train_project_progress *progress, nbrdf_error *err) {
  train_samples data;
  memset(&data, 0, sizeof data);
  nbrdf_status st = train_samples_generate_all(&data, n, params, family, err);
  memset(out, 0, n * (size_t)dec->cfg.latent_dim * sizeof(float));
  model_fit_options o = MODEL_FIT_OPTIONS_DEFAULT;
  o.rows_per_brdf = 256;
  o.lr_latent = 2e-2f;
  o.decay_every = steps / 4 > 0 ? steps / 4 : 1;
  o.decay_gamma = 0.5f;
  o.seed = seed;
  model_fit *fit = NULL;
  model_samples view = train_samples_view(&data);
  if (!st) st = model_fit_create(dec, n, out, &o, &fit, err);
  for (int i = 0; i < steps && !st; i++) {
    if (progress &&
        nbrdf_ticker_tick(progress->tk, progress->stage, progress->done0 + i, progress->total, 0))
      st = nbrdf_fail(err, NBRDF_ERR_CANCELLED, "%s: cancelled at step %d of %d", progress->stage,
                      i, steps);
    else
      st = model_fit_step(fit, &view, NULL, err);
  }
  model_fit_destroy(fit);
  train_samples_free(&data);
  return st;
}
