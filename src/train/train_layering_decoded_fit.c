/* The loop of the decoded-loss layering training (train_layering.h):
 * epochs of shuffled batches, Adam, validation, checkpoints. */
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "core/error.h"
#include "core/rng.h"
#include "core/progress.h"
#include "train/checkpoint.h"
#include "train/run_log.h"
#include "train/train_layering.h"

#define CHECKPOINT_FORMAT "nbrdf-train-layering-checkpoint"

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

typedef struct trainer {
  const train_samples *data;
  model_decoder *dec;
  model_layering *net;
  const train_layering_settings *s;
  train_layering_decoded *engine;
  float *grad;
  nbrdf_adam *adam;
} trainer;

static nbrdf_status add(nbrdf_st_writer *w, const char *name, size_t n, const float *x,
                        nbrdf_error *err) {
  int64_t shape[1] = {(int64_t)n};
  return nbrdf_st_writer_add_borrowed(w, name, 1, shape, x, err);
}

/* The settings a checkpoint must share with the run that resumes it. */
static void run_key(const trainer *t, char *out, size_t size) {
  char data[1024];
  train_checkpoint_data_key(t->data, data, sizeof data);
  const train_layering_settings *s = t->s;
  snprintf(out, size,
           "%s;D=%d;batch=%d;rows=%d;lr=%g;decay=%d/%g;val=%d;seed=%" PRIu64 ";loss=%s;%s",
           s->preset, t->net->latent_dim, s->batch, s->rows_per_pair, (double)s->lr, s->decay_every,
           (double)s->decay_gamma, s->validation_every, s->seed, model_loss_name(s->loss), data);
  /* Only when on, so that checkpoints of runs without the penalty still resume. */
  if (s->energy.lambda > 0.0f) {
    size_t len = strlen(out);
    snprintf(out + len, size > len ? size - len : 0, ";energy=%g/%d/%d", (double)s->energy.lambda,
             s->energy.n_theta, s->energy_brdfs);
  }
}

/* `epoch` epochs done, and `batch` batches of the next one (a run cancelled
 * inside an epoch resumes at the next batch, exactly: the epoch's shuffle and
 * each step's draws are functions of the seed, the epoch and the step). */
static nbrdf_status save_checkpoint(const trainer *t, int epoch, int64_t batch, nbrdf_error *err) {
  nbrdf_st_writer *w = NULL;
  char key[2048], ep[32], bt[32];
  size_t n = nbrdf_nn_param_count(t->net->nn);
  run_key(t, key, sizeof key);
  snprintf(ep, sizeof ep, "%d", epoch);
  snprintf(bt, sizeof bt, "%" PRId64, batch);
  nbrdf_status st = nbrdf_st_writer_create(&w, err);
  if (!st) st = nbrdf_st_writer_set_metadata(w, "nbrdf.format", CHECKPOINT_FORMAT, err);
  if (!st) st = nbrdf_st_writer_set_metadata(w, "nbrdf.run", key, err);
  if (!st) st = nbrdf_st_writer_set_metadata(w, "nbrdf.epoch", ep, err);
  if (!st) st = nbrdf_st_writer_set_metadata(w, "nbrdf.batch", bt, err);
  if (!st) st = add(w, "layering.params", n, nbrdf_nn_params_const(t->net->nn), err);
  if (!st) st = add(w, "adam.m", n, nbrdf_adam_moment(t->adam, 0), err);
  if (!st) st = add(w, "adam.v", n, nbrdf_adam_moment(t->adam, 1), err);
  if (!st) st = nbrdf_st_writer_save(w, t->s->checkpoint, NULL, err);
  nbrdf_st_writer_destroy(w);
  return st;
}

/* Restores a checkpoint if there is one; *epoch = epochs done and *batch =
 * batches done of the next epoch (0 and 0 without; checkpoints written before
 * nbrdf.batch existed are at an epoch's end). */
static nbrdf_status load_checkpoint(trainer *t, int64_t steps_per_epoch, int *epoch,
                                    int64_t *batch, nbrdf_error *err) {
  *epoch = 0, *batch = 0;
  /* No checkpoint yet: start afresh (anything else, a FIFO included, is for
   * nbrdf_st_open to refuse: opening it here could block). */
  struct stat sb;
  if (stat(t->s->checkpoint, &sb) != 0 && errno == ENOENT) return NBRDF_OK;
  nbrdf_st_reader *r = NULL;
  nbrdf_status st = nbrdf_st_open(t->s->checkpoint, &r, err);
  if (st) return st;
  char key[2048];
  run_key(t, key, sizeof key);
  const char *fmt = nbrdf_st_metadata_get(r, "nbrdf.format"),
             *k = nbrdf_st_metadata_get(r, "nbrdf.run");
  const char *e = nbrdf_st_metadata_get(r, "nbrdf.epoch");
  const char *b = nbrdf_st_metadata_get(r, "nbrdf.batch");
  char *end = NULL, *bend = NULL;
  long ep = e ? strtol(e, &end, 10) : -1;
  long long bt = b ? strtoll(b, &bend, 10) : 0;
  if (b && (*bend || bt < 0 || bt >= steps_per_epoch)) bt = -1;
  if (!fmt || strcmp(fmt, CHECKPOINT_FORMAT) || !k || strcmp(k, key) || !e || *end || ep < 0 ||
      bt < 0)
    st = nbrdf_fail(err, NBRDF_ERR_MISMATCH,
                    "%s: a checkpoint of another layering run (data, preset or settings differ); "
                    "remove it or give the same settings",
                    t->s->checkpoint);
  size_t n = nbrdf_nn_param_count(t->net->nn);
  int64_t shape[1] = {(int64_t)n};
  if (!st)
    st = nbrdf_st_expect_copy(r, "layering.params", 1, shape, nbrdf_nn_params(t->net->nn), err);
  if (!st) st = nbrdf_st_expect_copy(r, "adam.m", 1, shape, nbrdf_adam_moment(t->adam, 0), err);
  if (!st) st = nbrdf_st_expect_copy(r, "adam.v", 1, shape, nbrdf_adam_moment(t->adam, 1), err);
  nbrdf_st_close(r);
  if (!st) {
    nbrdf_adam_set_steps(t->adam, (int64_t)ep * steps_per_epoch + bt);
    *epoch = (int)ep, *batch = bt;
  }
  return st;
}

static void shuffle(size_t *idx, size_t n, uint64_t seed, int epoch) {
  nbrdf_rng rng;
  nbrdf_rng_init(&rng, seed, 0x6c61796572000000u + (uint64_t)epoch);
  for (size_t i = 0; i < n; i++)
    idx[i] = i;
  for (size_t i = n; i > 1; i--) { /* Fisher–Yates */
    size_t j = (size_t)(nbrdf_rng_uniform(&rng) * (double)i), x = idx[i - 1];
    idx[i - 1] = idx[j], idx[j] = x;
  }
}

static nbrdf_status setup(trainer *t, size_t D, nbrdf_error *err) {
  const train_layering_settings *s = t->s;
  nbrdf_status st = model_layering_create(s->preset, (int)D, s->seed, &t->net, err);
  if (!st && s->init) {
    size_t n = nbrdf_nn_param_count(t->net->nn);
    if (strcmp(s->init->preset, s->preset) || nbrdf_nn_param_count(s->init->nn) != n ||
        s->init->latent_dim != (int)D)
      return nbrdf_fail(err, NBRDF_ERR_MISMATCH,
                        "train layering: the initial weights are of preset '%s', the run's is '%s'",
                        s->init->preset, s->preset);
    memcpy(nbrdf_nn_params(t->net->nn), nbrdf_nn_params_const(s->init->nn), n * sizeof(float));
  }
  if (!st)
    st = train_layering_decoded_create(t->net, t->dec, t->data, s->batch, s->rows_per_pair, s->loss,
                                       s->seed, &t->engine, err);
  if (!st) st = train_layering_decoded_set_energy(t->engine, &s->energy, s->energy_brdfs, err);
  if (st) return st;
  if (!(t->grad = malloc(nbrdf_nn_param_count(t->net->nn) * sizeof(float))))
    return nbrdf_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  return NBRDF_OK;
}

nbrdf_status train_layering_fit_decoded(const train_samples *data, model_decoder *dec,
                                        const model_base_table tables[2],
                                        const train_layering_settings *s, model_layering **out,
                                        train_layering_result *r, nbrdf_error *err) {
  memset(r, 0, sizeof *r);
  r->val_loss = r->val_decoded = r->val_decoded_oracle = NAN;
  *out = NULL;
  layering_pairs train, val;
  nbrdf_status st =
      layering_pairs_make(data, NULL, tables, 2, s->validation_every, &train, &val, err);
  if (st) return st;
  r->pairs = train.n, r->validation_pairs = val.n;
  trainer t = {.data = data, .dec = dec, .s = s};
  size_t D = (size_t)tables[0].dim, B = (size_t)s->batch;
  size_t *idx = malloc(train.n * sizeof *idx);
  int64_t steps_per_epoch = (int64_t)((train.n + B - 1) / B);
  run_log log = {0};
  if (!idx) st = nbrdf_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  if (!st) st = setup(&t, D, err);
  if (!st) {
    nbrdf_adam_options ao = NBRDF_ADAM_OPTIONS_DEFAULT;
    ao.lr = s->lr;
    ao.decay_every = s->decay_every * (int)steps_per_epoch; /* epochs → steps */
    ao.decay_gamma = s->decay_gamma;
    st = nbrdf_adam_create(nbrdf_nn_param_count(t.net->nn), &ao, &t.adam, err);
  }
  int epoch = 0;
  int64_t first_batch = 0; /* of the first epoch run here: > 0 when resuming inside it */
  if (!st && s->checkpoint) st = load_checkpoint(&t, steps_per_epoch, &epoch, &first_batch, err);
  r->resumed_from = epoch;
  /* Ctrl-C (the callback's answer) is heard after every batch, not only at an
   * epoch's end: an epoch of the shipped recipe takes minutes. */
  nbrdf_ticker ticker;
  nbrdf_ticker_init(&ticker, s->progress, s->user, NULL);
  if (!st && s->log_path)
    st = run_log_open(&log, s->log_path, "epoch,seconds,train_loss,val_decoded,lr", epoch, err);
  double t0 = now_s(), last_ckpt = t0;
  for (; epoch < s->epochs && !st; epoch++) {
    shuffle(idx, train.n, s->seed, epoch);
    double sum = 0.0;
    size_t rows = 0;
    int stop = 0;
    for (size_t k0 = (size_t)first_batch * B; k0 < train.n && !st && !stop; k0 += B) {
      int m = (int)(train.n - k0 < B ? train.n - k0 : B);
      int64_t step = (int64_t)epoch * steps_per_epoch + (int64_t)(k0 / B);
      double l = 0.0;
      memset(t.grad, 0, nbrdf_nn_param_count(t.net->nn) * sizeof *t.grad);
      st = train_layering_decoded_gradient(t.engine, &train, idx + k0, m, step, t.grad, &l, err);
      sum += l * m, rows += (size_t)m;
      if (!st) st = nbrdf_adam_step(t.adam, nbrdf_nn_params(t.net->nn), t.grad, err);
      if (!st && k0 + (size_t)m < train.n &&
          nbrdf_ticker_tick(&ticker, "train layering", epoch + (double)(k0 + m) / (double)train.n,
                            s->epochs, 0)) {
        stop = 1;
        if (s->checkpoint) st = save_checkpoint(&t, epoch, (int64_t)(k0 / B) + 1, err);
        if (!st)
          st = nbrdf_fail(err, NBRDF_ERR_CANCELLED,
                          "train layering: cancelled in epoch %d after batch %d of %d%s", epoch + 1,
                          (int)(k0 / B) + 1, (int)steps_per_epoch,
                          s->checkpoint ? " (resumable)" : "");
      }
    }
    first_batch = 0;
    if (st) break;
    r->train_loss = sum / (double)(rows ? rows : 1);
    int last = epoch + 1 == s->epochs;
    if (val.n && (epoch % 5 == 4 || last))
      st = train_layering_decoded_loss(t.net, dec, s->loss, data, &val, &r->val_decoded, err);
    if (!st)
      run_log_row(&log, "%d,%.1f,%.6g,%.6g,%.4g", epoch + 1, now_s() - t0, r->train_loss,
                  r->val_decoded, (double)nbrdf_adam_lr(t.adam, 0));
    int cancel = !st && nbrdf_ticker_tick(&ticker, "train layering", epoch + 1, s->epochs, 1);
    if (!st && s->checkpoint && (last || cancel || now_s() - last_ckpt >= s->checkpoint_seconds)) {
      st = save_checkpoint(&t, epoch + 1, 0, err);
      last_ckpt = now_s();
    }
    if (!st && cancel)
      st = nbrdf_fail(err, NBRDF_ERR_CANCELLED,
                      "train layering: cancelled after epoch %d (resumable)", epoch + 1);
  }
  r->epochs_done = epoch;
  if (!st && val.n && isnan(r->val_decoded))
    st = train_layering_decoded_loss(t.net, dec, s->loss, data, &val, &r->val_decoded, err);
  run_log_close(&log);
  nbrdf_adam_destroy(t.adam);
  train_layering_decoded_destroy(t.engine);
  free(idx), free(t.grad);
  layering_pairs_free(&train), layering_pairs_free(&val);
  if (st) {
    model_layering_destroy(t.net);
    return st;
  }
  *out = t.net;
  return NBRDF_OK;
}
