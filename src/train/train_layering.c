#include "train/train_layering.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/rng.h"
#include "train/epoch_shuffle.h"
#include "train/layering_trainer.h"

/* Mean squared error over pairs [lo, lo + m) in the order `idx`; with
 * `backward`, accumulates the gradient into grad. */
static nbrdf_status batch_loss(model_layering *net, model_runner *run,
                               const train_layering_pairs *p, const size_t *idx, size_t m,
                               float *grad, float *dy, double *loss, nbrdf_error *err) {
  size_t D = (size_t)net->latent_dim, in = 2 * D + 2;
  float *x = run->x;
  for (size_t r = 0; r < m; r++) {
    size_t i = idx[r];
    model_layering_fill_inputs(net, 1, p->top + i * D, p->bottom + i * D, p->albedo + i,
                               p->sigma_t + i, x + r * in);
  }
  nbrdf_status st = nn_forward(net->nn, run->ws, x, (int)m, run->y, err);
  if (st) return st;
  double sum = 0.0, scale = 1.0 / ((double)m * (double)D);
  for (size_t r = 0; r < m; r++)
    for (size_t j = 0; j < D; j++) {
      double e = (double)run->y[r * D + j] - p->target[idx[r] * D + j];
      sum += e * e;
      if (dy) dy[r * D + j] = (float)(2.0 * e * scale);
    }
  *loss = sum * scale;
  if (grad) st = nn_backward(net->nn, run->ws, dy, NULL, grad, err);
  return st;
}

static nbrdf_status eval_all(model_layering *net, model_runner *run, const train_layering_pairs *p,
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

uint64_t train_layering_tables_hash(const model_base_table tables[2]) {
  uint64_t h = TRAIN_HASH_START;
  for (int k = 0; k < 2; k++) {
    const model_base_table *t = &tables[k];
    h = train_hash_floats(h, t->axis[0], (size_t)t->n[0]);
    h = train_hash_floats(h, t->axis[1], (size_t)t->n[1]);
    h = train_hash_floats(h, t->latents, (size_t)t->n[0] * (size_t)t->n[1] * (size_t)t->dim);
  }
  return h;
}

/* The latent-loss run (its shuffles: train/epoch_shuffle.h). */
typedef struct latent_run {
  model_layering *net;
  model_decoder *dec;
  const train_samples *data;
  const train_layering_settings *s;
  const train_layering_pairs *train, *val;
  model_runner run;
  train_epoch_shuffle shuffle;
  size_t *eval_idx;
  float *dy, *grad;
  train_layering_result *r;
} latent_run;

static nbrdf_status latent_batch(void *user, const size_t *idx, size_t m, int64_t step,
                                 double *loss, nbrdf_error *err) {
  (void)step;
  latent_run *t = user;
  return batch_loss(t->net, &t->run, t->train, idx, m, t->grad, t->dy, loss, err);
}

/* Every 10 epochs and at the last: the validation losses and a log row. */
static nbrdf_status latent_epoch_end(void *user, trainer *tr, int epoch, nbrdf_error *err) {
  latent_run *t = user;
  train_layering_result *r = t->r;
  if (epoch % 10 != 0 && epoch != t->s->epochs) return NBRDF_OK;
  nbrdf_status st = t->val->n ? eval_all(t->net, &t->run, t->val, t->eval_idx, &r->val_loss,
                                         &r->target_mean_square, err)
                              : NBRDF_OK;
  if (!st && t->dec && t->val->n)
    st = train_layering_decoded_loss(t->net, t->dec, t->s->loss, t->data, t->val, &r->val_decoded,
                                     err);
  trainer_log(tr, "%d,%.6g,%.6g,%.6g,%.4g", epoch, r->train_loss, r->val_loss, r->val_decoded,
              trainer_lr(tr, 0));
  return st;
}

static void latent_options(const latent_run *t, const float *latents, char *out, size_t size) {
  const train_layering_settings *s = t->s;
  char data[1024], num[32];
  train_checkpoint_data_key(t->data, data, sizeof data);
  size_t D = (size_t)t->net->latent_dim;
  out[0] = '\0';
  trainer_option(out, size, "preset", "%s", s->preset);
  trainer_option(out, size, "latent-dim", "%zu", D);
  trainer_option(out, size, "batch", "%d", s->batch);
  trainer_option(out, size, "lr", "%s", trainer_float_text(s->lr, num));
  trainer_option(out, size, "decay-every", "%d", s->decay_every);
  trainer_option(out, size, "decay-gamma", "%s", trainer_float_text(s->decay_gamma, num));
  trainer_option(out, size, "validation-every", "%d", s->validation_every);
  trainer_option(out, size, "seed", "%llu", (unsigned long long)s->seed);
  trainer_option(out, size, "data", "%s", data);
  trainer_option(
      out, size, "latents", "%016llx",
      (unsigned long long)train_hash_floats(TRAIN_HASH_START, latents, t->data->n_brdfs * D));
}

nbrdf_status train_layering_fit(const train_samples *data, const float *latents, model_decoder *dec,
                                const model_base_table tables[2], const train_layering_settings *s,
                                model_layering **out, train_layering_result *r, nbrdf_error *err) {
  memset(r, 0, sizeof *r);
  r->val_decoded = r->val_decoded_oracle = NAN;
  *out = NULL;
  train_layering_pairs train, val;
  nbrdf_status st =
      train_layering_pairs_make(data, latents, tables, 1, s->validation_every, &train, &val, err);
  if (st) return st;
  r->pairs = train.n, r->validation_pairs = val.n;
  size_t D = (size_t)tables[0].dim, B = (size_t)s->batch;
  latent_run t = {.dec = dec, .data = data, .s = s, .train = &train, .val = &val, .r = r};
  int shuffle_ok = train_epoch_shuffle_init(&t.shuffle, train.n, s->seed, 0x6c61796572u);
  t.eval_idx = malloc((val.n ? val.n : 1) * sizeof *t.eval_idx);
  t.dy = malloc(B * D * sizeof *t.dy);
  char options[4096];
  st = model_layering_create(s->preset, (int)D, s->seed, &t.net, err);
  if (!st) st = model_runner_create(t.net->nn, (int)B, NBRDF_NN_TRAIN, &t.run, err);
  if (!st && !(t.grad = malloc(nn_param_count(t.net->nn) * sizeof *t.grad)))
    st = core_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  if (!st && (!shuffle_ok || !t.eval_idx || !t.dy))
    st = core_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  if (!st) {
    latent_options(&t, latents, options, sizeof options);
    trainer_word words[3];
    train_epoch_shuffle_words(&t.shuffle, words);
    train_layering_trainer lt = {.net = t.net,
                                 .grad = t.grad,
                                 .n = train.n,
                                 .shuffle = &t.shuffle,
                                 .format = "nbrdf-train-layering-latent-checkpoint",
                                 .options = options,
                                 .log_header = "epoch,train_loss,val_loss,val_decoded,lr",
                                 .words = words,
                                 .n_words = 3,
                                 .user = &t,
                                 .batch = latent_batch,
                                 .epoch_end = latent_epoch_end};
    st = train_layering_trainer_run(s, &lt, r, err);
  }
  if (!st && dec && val.n)
    st = train_layering_decoded_loss(NULL, dec, s->loss, data, &val, &r->val_decoded_oracle, err);
  model_runner_destroy(&t.run);
  train_epoch_shuffle_free(&t.shuffle);
  free(t.eval_idx), free(t.dy), free(t.grad);
  train_layering_pairs_free(&train), train_layering_pairs_free(&val);
  if (st) {
    model_layering_destroy(t.net);
    return st;
  }
  *out = t.net;
  return NBRDF_OK;
}
