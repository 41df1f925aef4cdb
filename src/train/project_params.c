#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/progress.h"
#include "train/dataset.h"
#include "train/projection.h"
#include "train/samples.h"
#include "train/table_fit.h"

void train_project_defaults(int steps, uint64_t seed, train_projection *p) {
  p->loss = MODEL_LOSS_L1_LOG1P;
  p->rows_per_brdf = 256;
  p->lr = 2e-2f;
  p->decay_every = steps / 4 > 0 ? steps / 4 : 1;
  p->decay_gamma = 0.5f;
  p->seed = seed;
  p->steps = steps;
  p->max_batch = 0;
}

nbrdf_status train_project_params(model_decoder *dec, size_t n, const train_params *params,
                                  uint64_t family, int steps, uint64_t seed, float *out,
                                  const train_project_progress *progress, nbrdf_error *err) {
  train_samples data;
  memset(&data, 0, sizeof data);
  nbrdf_status st = train_samples_generate_all(&data, n, params, family, err);
  memset(out, 0, n * (size_t)dec->cfg.latent_dim * sizeof(float));
  train_projection p;
  train_project_defaults(steps, seed, &p);
  model_samples view = train_samples_view(&data);
  trainer_options to = TRAINER_OPTIONS_DEFAULT;
  if (progress) {
    to.stage = progress->stage, to.ticker = progress->tk;
    to.progress_offset = progress->done0, to.progress_total = progress->total;
  }
  if (!st) st = train_project_sets(dec, 1, &view, &out, &p, &to, NULL, err);
  train_samples_free(&data);
  return st;
}
