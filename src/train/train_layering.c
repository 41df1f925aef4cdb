#include "train/train_layering.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/progress.h"
#include "core/rng.h"
#include "train/run_log.h"

/* Mean squared error over pairs [lo, lo + m) in the order `idx`; with
 * `backward`, accumulates the gradient into grad. */
static nbrdf_status batch_loss(model_layering *net, model_runner *run, const layering_pairs *p,
                               const size_t *idx, size_t m, float *grad, float *dy, double *loss,
                               nbrdf_error *err) {
  size_t D = (size_t)net->latent_dim, in = 2 * D + 2;
  float *x = run->x;
  for (size_t r = 0; r < m; r++) {
    size_t i = idx[r];
    model_layering_fill_inputs(net, 1, p->top + i * D, p->bottom + i * D, p->albedo + i,
                               p->sigma_t + i, x + r * in);
  }
  nbrdf_status st = nbrdf_nn_forward(net->nn, run->ws, x, (int)m, run->y, err);
  if (st) return st;
  double sum = 0.0, scale = 1.0 / ((double)m * (double)D);
  for (size_t r = 0; r < m; r++)
    for (size_t j = 0; j < D; j++) {
      double e = (double)run->y[r * D + j] - p->target[idx[r] * D + j];
      sum += e * e;
      if (dy) dy[r * D + j] = (float)(2.0 * e * scale);
    }
  *loss = sum * scale;
  if (grad) st = nbrdf_nn_backward(net->nn, run->ws, dy, NULL, grad, err);
  return st;
}

static nbrdf_status eval_all(model_layering *net, model_runner *run, const layering_pairs *p,
                             size_t *idx, double *loss, double *mean_sq, nbrdf_error *err) {
  size_t D = (size_t)net->latent_dim, B = (size_t)run->max_batch;
  double sum = 0.0, sq = 0.0;
  nbrdf_status st = NBRDF_OK;
  for (size_t i = 0; i < p->n; i++)
    idx[i] = i;
  for (size_t k0 = 0; k0 < p->n && !st; k0 += B) {
    size_t m = p->n - k0 < B ? p->n - k0 : B;
    double l = 0.0;
    st = batch_loss(net, run, p, idx + k0, m, NULL, NULL, &l, err);
    sum += l * (double)m;
  }
  for (size_t k = 0; k < p->n * D; k++)
    sq += (double)p->target[k] * p->target[k];
  *loss = sum / (double)p->n;
  if (mean_sq) *mean_sq = sq / ((double)p->n * (double)D);
  return st;
}

nbrdf_status train_layering_fit(const train_samples *data, const float *latents, model_decoder *dec,
                                const model_base_table tables[2], const train_layering_settings *s,
                                model_layering **out, train_layering_result *r, nbrdf_error *err) {
  memset(r, 0, sizeof *r);
  r->val_decoded = r->val_decoded_oracle = NAN;
  *out = NULL;
  layering_pairs train, val;
  nbrdf_status st =
      layering_pairs_make(data, latents, tables, 1, s->validation_every, &train, &val, err);
  if (st) return st;
  r->pairs = train.n, r->validation_pairs = val.n;
  model_layering *net = NULL;
  model_runner run = {0};
  nbrdf_adam *adam = NULL;
  size_t D = (size_t)tables[0].dim, B = (size_t)s->batch;
  size_t *idx = malloc((train.n > val.n ? train.n : val.n) * sizeof *idx);
  float *dy = malloc(B * D * sizeof *dy), *grad = NULL;
  run_log log = {0};
  st = model_layering_create(s->preset, (int)D, s->seed, &net, err);
  if (!st) st = model_runner_create(net->nn, (int)B, NBRDF_NN_TRAIN, &run, err);
  if (!st && !(grad = malloc(nbrdf_nn_param_count(net->nn) * sizeof *grad)))
    st = nbrdf_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  if (!st && (!idx || !dy)) st = nbrdf_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  if (!st) {
    nbrdf_adam_options ao = NBRDF_ADAM_OPTIONS_DEFAULT;
    ao.lr = s->lr;
    ao.decay_every = s->decay_every * (int)((train.n + B - 1) / B); /* epochs → steps */
    ao.decay_gamma = s->decay_gamma;
    st = nbrdf_adam_create(nbrdf_nn_param_count(net->nn), &ao, &adam, err);
  }
  if (!st && s->log_path)
    st = run_log_open(&log, s->log_path, "epoch,train_loss,val_loss,val_decoded,lr", 0, err);
  nbrdf_rng rng;
  nbrdf_rng_init(&rng, s->seed, 0x6c61796572u);
  nbrdf_ticker tk;
  nbrdf_ticker_init(&tk, s->progress, s->user, NULL);
  for (int e = 0; e < s->epochs && !st; e++) {
    for (size_t i = 0; i < train.n; i++)
      idx[i] = i;
    for (size_t i = train.n; i > 1; i--) { /* Fisher–Yates */
      size_t j = (size_t)(nbrdf_rng_uniform(&rng) * (double)i), t = idx[i - 1];
      idx[i - 1] = idx[j], idx[j] = t;
    }
    double sum = 0.0;
    for (size_t k0 = 0; k0 < train.n && !st; k0 += B) {
      /* an epoch of many rows takes seconds: cancel and progress between batches */
      if (nbrdf_ticker_tick(&tk, "train layering", e + (double)k0 / (double)train.n, s->epochs,
                            0)) {
        st = nbrdf_fail(err, NBRDF_ERR_CANCELLED, "train layering: cancelled in epoch %d", e + 1);
        break;
      }
      size_t m = train.n - k0 < B ? train.n - k0 : B;
      double l = 0.0;
      memset(grad, 0, nbrdf_nn_param_count(net->nn) * sizeof *grad);
      st = batch_loss(net, &run, &train, idx + k0, m, grad, dy, &l, err);
      sum += l * (double)m;
      if (!st) st = nbrdf_adam_step(adam, nbrdf_nn_params(net->nn), grad, err);
    }
    r->train_loss = sum / (double)train.n;
    if (!st && (e % 10 == 9 || e == s->epochs - 1)) {
      st = val.n ? eval_all(net, &run, &val, idx, &r->val_loss, &r->target_mean_square, err)
                 : NBRDF_OK;
      if (!st && dec && val.n)
        st = train_layering_decoded_loss(net, dec, s->loss, data, &val, &r->val_decoded, err);
      run_log_row(&log, "%d,%.6g,%.6g,%.6g,%.4g", e + 1, r->train_loss, r->val_loss, r->val_decoded,
                  (double)nbrdf_adam_lr(adam, 0));
    }
    if (!st && nbrdf_ticker_tick(&tk, "train layering", e + 1, s->epochs, e + 1 == s->epochs))
      st = nbrdf_fail(err, NBRDF_ERR_CANCELLED, "train layering: cancelled");
  }
  if (!st && dec && val.n)
    st = train_layering_decoded_loss(NULL, dec, s->loss, data, &val, &r->val_decoded_oracle, err);
  r->epochs_done = s->epochs;
  run_log_close(&log);
  nbrdf_adam_destroy(adam);
  model_runner_destroy(&run);
  free(idx), free(dy), free(grad);
  layering_pairs_free(&train), layering_pairs_free(&val);
  if (st) {
    model_layering_destroy(net);
    return st;
  }
  *out = net;
  return NBRDF_OK;
}
