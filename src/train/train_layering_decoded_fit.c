/* The decoded-loss layering training (train_layering.h) as a fit of the
 * trainer (train/trainer.h): epochs of shuffled batches, validation, the log. */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/progress.h"
#include "train/checkpoint.h"
#include "train/epoch_shuffle.h"
#include "train/layering_trainer.h"
#include "train/train_layering.h"

#define CHECKPOINT_FORMAT "nbrdf-train-layering-checkpoint"

typedef struct decoded_run {
  const train_samples *data;
  model_decoder *dec;
  model_layering *net;
  const train_layering_settings *s;
  train_layering_decoded *engine;
  float *grad;
  const train_layering_pairs *train, *val;
  train_epoch_shuffle shuffle; /* per epoch: a function of the seed and the epoch */
  uint64_t tables_hash;
  int64_t steps_per_epoch; /* for legacy checkpoints' epoch and batch */
  train_layering_result *r;
} decoded_run;

/* The settings a checkpoint written before nbrdf.options had to share with the
 * run that resumes it (one string). */
static void run_key(const decoded_run *t, char *out, size_t size) {
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

/* A checkpoint from before nbrdf.options: the run key as it was checked
 * then; the step from its epoch and batch. */
static nbrdf_status legacy(void *user, const nn_st_reader *r, int64_t *step, nbrdf_error *err) {
  decoded_run *t = user;
  char key[2048];
  run_key(t, key, sizeof key);
  const char *k = nn_st_metadata_get(r, "nbrdf.run");
  const char *e = nn_st_metadata_get(r, "nbrdf.epoch");
  const char *b = nn_st_metadata_get(r, "nbrdf.batch");
  char *end = NULL, *bend = NULL;
  long ep = e ? strtol(e, &end, 10) : -1;
  long long bt = b ? strtoll(b, &bend, 10) : 0; /* older still: at an epoch's end */
  if (b && (*bend || bt < 0 || bt >= t->steps_per_epoch)) bt = -1;
  if (!k || strcmp(k, key) || !e || *end || ep < 0 || bt < 0)
    return core_fail(err, NBRDF_ERR_MISMATCH,
                     "%s: a checkpoint of another layering run (data, preset or settings "
                     "differ); remove it or give the same settings",
                     nn_st_label(r));
  *step = (int64_t)ep * t->steps_per_epoch + bt;
  return NBRDF_OK;
}

/* The options a resume must share (not the epoch count: more epochs extend a run). */
static void run_options(const decoded_run *t, char *out, size_t size) {
  const train_layering_settings *s = t->s;
  char data[1024], num[32];
  train_checkpoint_data_key(t->data, data, sizeof data);
  out[0] = '\0';
  trainer_option(out, size, "preset", "%s", s->preset);
  trainer_option(out, size, "latent-dim", "%d", t->net->latent_dim);
  trainer_option(out, size, "batch", "%d", s->batch);
  trainer_option(out, size, "rows", "%d", s->rows_per_pair);
  trainer_option(out, size, "lr", "%s", trainer_float_text(s->lr, num));
  trainer_option(out, size, "decay-every", "%d", s->decay_every);
  trainer_option(out, size, "decay-gamma", "%s", trainer_float_text(s->decay_gamma, num));
  trainer_option(out, size, "validation-every", "%d", s->validation_every);
  trainer_option(out, size, "seed", "%llu", (unsigned long long)s->seed);
  trainer_option(out, size, "loss", "%s", model_loss_name(s->loss));
  trainer_option(out, size, "data", "%s", data);
  trainer_option(out, size, "decoder weights", "%016llx",
                 (unsigned long long)train_hash_floats(
                     TRAIN_HASH_START, nn_params_const(t->dec->nn), nn_param_count(t->dec->nn)));
  trainer_option(out, size, "tables", "%016llx", (unsigned long long)t->tables_hash);
  if (s->energy.lambda > 0.0f) { /* only when on: runs without the penalty still resume */
    trainer_option(out, size, "energy", "%g/%d/%d", (double)s->energy.lambda, s->energy.n_theta,
                   s->energy_brdfs);
    if (s->energy.floor_margin >= 0.0f)
      trainer_option(out, size, "energy-floor", "%g", (double)s->energy.floor_margin);
  }
}

static nbrdf_status setup(decoded_run *t, size_t D, nbrdf_error *err) {
  const train_layering_settings *s = t->s;
  nbrdf_status st = model_layering_create(s->preset, (int)D, s->seed, &t->net, err);
  if (!st && s->init) {
    size_t n = nn_param_count(t->net->nn);
    if (strcmp(s->init->preset, s->preset) || nn_param_count(s->init->nn) != n ||
        s->init->latent_dim != (int)D)
      return core_fail(err, NBRDF_ERR_MISMATCH,
                       "train layering: the initial weights are of preset '%s', the run's is '%s'",
                       s->init->preset, s->preset);
    memcpy(nn_params(t->net->nn), nn_params_const(s->init->nn), n * sizeof(float));
  }
  if (!st)
    st = train_layering_decoded_create(t->net, t->dec, t->data, s->batch, s->rows_per_pair, s->loss,
                                       s->seed, &t->engine, err);
  if (!st) st = train_layering_decoded_set_energy(t->engine, &s->energy, s->energy_brdfs, err);
  if (st) return st;
  if (!(t->grad = malloc(nn_param_count(t->net->nn) * sizeof(float))))
    return core_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  return NBRDF_OK;
}

/* The loss of m pairs of the epoch's shuffle (a function of the seed and the
 * epoch), rows from stream `step`. */
static nbrdf_status batch(void *user, const size_t *idx, size_t m, int64_t step, double *loss,
                          nbrdf_error *err) {
  decoded_run *t = user;
  return train_layering_decoded_gradient(t->engine, t->train, idx, (int)m, step, t->grad, loss,
                                         err);
}

/* Validation every 5 epochs and at the last, a log row. */
static nbrdf_status epoch_end(void *user, trainer *tr, int epoch, nbrdf_error *err) {
  decoded_run *t = user;
  nbrdf_status st = NBRDF_OK;
  if (t->val->n && (epoch % 5 == 0 || epoch == t->s->epochs))
    st = train_layering_decoded_loss(t->net, t->dec, t->s->loss, t->data, t->val,
                                     &t->r->val_decoded, err);
  if (!st)
    trainer_log(tr, "%d,%.1f,%.6g,%.6g,%.4g", epoch, trainer_seconds(tr), t->r->train_loss,
                t->r->val_decoded, trainer_lr(tr, 0));
  return st;
}

nbrdf_status train_layering_fit_decoded(const train_samples *data, model_decoder *dec,
                                        const model_base_table tables[2],
                                        const train_layering_settings *s, model_layering **out,
                                        train_layering_result *r, nbrdf_error *err) {
  memset(r, 0, sizeof *r);
  r->val_loss = r->val_decoded = r->val_decoded_oracle = NAN;
  *out = NULL;
  train_layering_pairs train, val;
  nbrdf_status st =
      train_layering_pairs_make(data, NULL, tables, 2, s->validation_every, &train, &val, err);
  if (st) return st;
  r->pairs = train.n, r->validation_pairs = val.n;
  size_t D = (size_t)tables[0].dim;
  decoded_run t = {.data = data, .dec = dec, .s = s, .train = &train, .val = &val, .r = r};
  t.steps_per_epoch = train_layering_steps_per_epoch(s, train.n);
  t.tables_hash = train_layering_tables_hash(tables);
  int shuffle_ok =
      train_epoch_shuffle_init_per_epoch(&t.shuffle, train.n, s->seed, 0x6c61796572000000u);
  char options[4096];
  if (!shuffle_ok) st = core_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  if (!st) st = setup(&t, D, err);
  if (!st) {
    run_options(&t, options, sizeof options);
    train_layering_trainer lt = {.net = t.net,
                                 .grad = t.grad,
                                 .n = train.n,
                                 .shuffle = &t.shuffle,
                                 .format = CHECKPOINT_FORMAT,
                                 .options = options,
                                 .log_header = "epoch,seconds,train_loss,val_decoded,lr",
                                 .user = &t,
                                 .batch = batch,
                                 .epoch_end = epoch_end,
                                 .legacy = legacy};
    st = train_layering_trainer_run(s, &lt, r, err);
  }
  if (!st && val.n && isnan(r->val_decoded))
    st = train_layering_decoded_loss(t.net, dec, s->loss, data, &val, &r->val_decoded, err);
  train_layering_decoded_destroy(t.engine);
  train_epoch_shuffle_free(&t.shuffle);
  free(t.grad);
  train_layering_pairs_free(&train), train_layering_pairs_free(&val);
  if (st) {
    model_layering_destroy(t.net);
    return st;
  }
  *out = t.net;
  return NBRDF_OK;
}
