#include "train/train_decoder.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "core/error.h"
#include "core/rng.h"
#include "model/autodecoder.h"
#include "train/checkpoint.h"
#include "train/dataset.h"
#include "train/energy_reference.h"
#include "train/run_log.h"
#include "train/samples.h"

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Held-out `rep` BRDFs (indices from TRAIN_VALIDATION_FIRST). */
static nbrdf_status make_validation(int n, train_samples *out, nbrdf_error *err) {
  memset(out, 0, sizeof *out);
  if (n <= 0) return NBRDF_OK;
  train_params *params = malloc((size_t)n * sizeof *params);
  if (!params) return nbrdf_fail(err, NBRDF_ERR_MEMORY, "validation: out of memory");
  uint64_t family = train_heldout_seed(TRAIN_HELDOUT_REP);
  for (int i = 0; i < n; i++)
    train_params_draw(family, train_heldout_kind(TRAIN_HELDOUT_REP),
                      TRAIN_VALIDATION_FIRST + (uint64_t)i, &params[i]);
  nbrdf_status st = train_samples_generate_all(out, (size_t)n, params, family, err);
  free(params);
  return st;
}

/* Mean loss of the validation BRDFs projected with the decoder frozen. */
static nbrdf_status validate(model_decoder *dec, const train_decoder_settings *s,
                             const train_samples *val, double *loss, nbrdf_error *err) {
  *loss = NAN;
  if (val->n_brdfs == 0) return NBRDF_OK;
  size_t nl = val->n_brdfs * (size_t)dec->cfg.latent_dim;
  float *lat = calloc(nl, sizeof *lat);
  if (!lat) return nbrdf_fail(err, NBRDF_ERR_MEMORY, "validation: out of memory");
  model_fit_options o = MODEL_FIT_OPTIONS_DEFAULT;
  o.loss = s->loss;
  o.rows_per_brdf = 256;
  o.lr_latent = 2e-2f;
  o.decay_every = 100;
  o.decay_gamma = 0.5f;
  o.seed = s->seed;
  model_fit *fit = NULL;
  model_samples view = train_samples_view(val);
  nbrdf_status st = model_fit_create(dec, val->n_brdfs, lat, &o, &fit, err);
  for (int i = 0; i < 300 && !st; i++)
    st = model_fit_step(fit, &view, NULL, err);
  if (!st) st = model_fit_eval_loss(fit, &view, NULL, loss, err);
  model_fit_destroy(fit);
  free(lat);
  return st;
}

static nbrdf_status join(char *out, size_t size, const char *dir, const char *name,
                         nbrdf_error *err) {
  if ((size_t)snprintf(out, size, "%s/%s", dir, name) >= size)
    return nbrdf_fail(err, NBRDF_ERR_ARGUMENT, "%s: path too long", dir);
  return NBRDF_OK;
}

static void init_latents(float *lat, size_t n, uint64_t seed) {
  /* Small random latents (DeepSDF's N(0, 0.01²)) so that BRDFs start apart. */
  nbrdf_rng rng;
  nbrdf_rng_init(&rng, seed, 0x6c6174656e7473u);
  for (size_t k = 0; k < n; k++)
    lat[k] = (float)(0.01 * nbrdf_rng_normal(&rng));
}

void train_decoder_settings_default(train_decoder_settings *s) {
  memset(s, 0, sizeof *s);
  model_decoder_preset("medium", 32, &s->arch, NULL);
  s->steps = 20000;
  s->rows_per_brdf = 16;
  s->lr_weights = 2e-3f;
  s->lr_latent = 1e-2f;
  s->latent_l2 = 1e-4f;
  s->decay_every = 5000;
  s->decay_gamma = 0.5f;
  s->loss = MODEL_LOSS_L1_LOG1P;
  s->seed = 1;
  s->checkpoint_seconds = 300.0;
  s->log_every = 50;
  s->validation_brdfs = 24;
  s->energy = (model_energy_options)MODEL_ENERGY_OPTIONS_DEFAULT;
  s->energy_brdfs = 32;
}

/* The per-BRDF loss weights of settings->brdf_weight, or NULL for uniform. */
static float *brdf_weights(const train_samples *d, double power) {
  if (power == 0.0) return NULL;
  float *w = malloc(d->n_brdfs * sizeof *w);
  if (!w) return NULL;
  double total = 0.0;
  for (size_t b = 0; b < d->n_brdfs; b++) {
    double m = 0.0;
    for (size_t i = d->offsets[b]; i < d->offsets[b + 1]; i++)
      m += log1p((double)d->f[i]);
    m /= (double)(d->offsets[b + 1] - d->offsets[b]);
    w[b] = (float)pow(fmax(m, 0.01), -power);
    total += w[b];
  }
  for (size_t b = 0; b < d->n_brdfs; b++)
    w[b] = (float)(w[b] * (double)d->n_brdfs / total);
  return w;
}

nbrdf_status train_decoder_run(const train_decoder_settings *s, train_decoder_result *r,
                               nbrdf_error *err) {
  memset(r, 0, sizeof *r);
  r->val_loss = NAN;
  char ckpt[4096], dec_path[4096], log_path[4096];
  nbrdf_status st = join(ckpt, sizeof ckpt, s->run_dir, "checkpoint.safetensors", err);
  if (!st) st = join(dec_path, sizeof dec_path, s->run_dir, "decoder.safetensors", err);
  if (!st) st = join(log_path, sizeof log_path, s->run_dir, "log.csv", err);
  if (st) return st;
  if (s->steps < 1 || s->rows_per_brdf < 1 || s->log_every < 1 || !(s->checkpoint_seconds > 0) ||
      !(s->brdf_weight >= 0.0 && s->brdf_weight <= 2.0))
    return nbrdf_fail(err, NBRDF_ERR_ARGUMENT,
                      "train decoder: steps, rows per BRDF, log interval and checkpoint "
                      "interval must be positive, the BRDF weight power in [0, 2]");
  if (mkdir(s->run_dir, 0777) != 0 && errno != EEXIST)
    return nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot create the run folder: %s", s->run_dir,
                      strerror(errno));

  train_samples data, val;
  memset(&val, 0, sizeof val);
  model_decoder *dec = NULL;
  model_fit *fit = NULL;
  train_energy *energy = NULL;
  float *lat = NULL;
  run_log log = {0};
  st = train_samples_load(s->n_data, s->data, &data, err);
  if (st) return st;
  st = make_validation(s->validation_brdfs, &val, err);
  size_t nl = data.n_brdfs * (size_t)s->arch.latent_dim;
  if (!st) st = model_decoder_create(&s->arch, s->seed, &dec, err);
  if (!st && !(lat = malloc(nl * sizeof *lat)))
    st = nbrdf_fail(err, NBRDF_ERR_MEMORY, "train decoder: out of memory for latents");
  if (!st) {
    init_latents(lat, nl, s->seed);
    model_fit_options o = MODEL_FIT_OPTIONS_DEFAULT;
    o.loss = s->loss;
    o.rows_per_brdf = s->rows_per_brdf;
    o.lr_latent = s->lr_latent;
    o.lr_weights = s->lr_weights;
    o.latent_l2 = s->latent_l2;
    o.decay_every = s->decay_every;
    o.decay_gamma = s->decay_gamma;
    o.seed = s->seed;
    st = model_fit_create(dec, data.n_brdfs, lat, &o, &fit, err);
  }
  if (!st) st = train_energy_create(dec, &data, &s->energy, s->energy_brdfs, &energy, err);
  int64_t step = 0;
  struct stat sb;
  if (!st && stat(ckpt, &sb) == 0) {
    st = train_checkpoint_load(ckpt, dec, fit, lat, data.n_brdfs, &data, &step, err);
    r->resumed_from = step;
  }
  if (!st) st = run_log_open(&log, log_path, "step,seconds,train_loss,val_loss,lr", step, err);
  model_samples view = train_samples_view(&data);
  float *weight = st ? NULL : brdf_weights(&data, s->brdf_weight);
  if (!st && s->brdf_weight != 0.0 && !weight)
    st = nbrdf_fail(err, NBRDF_ERR_MEMORY, "train decoder: out of memory for BRDF weights");
  view.weight = weight;
  double t0 = now_s(), last_ckpt = t0, sum = 0.0;
  int count = 0, stop = 0;
  r->train_loss = NAN;
  while (!st && step < s->steps && !stop) {
    double loss;
    st = train_energy_fit_step(energy, fit, &view, lat, step, &loss, NULL, err);
    if (st) break;
    step++;
    sum += loss, count++;
    double t = now_s();
    if (s->max_seconds > 0 && t - t0 >= s->max_seconds) stop = 1;
    if (s->progress && s->progress(s->user, "train decoder", (double)step, (double)s->steps))
      stop = 1;
    int last = stop || step == s->steps;
    if (step % s->log_every == 0 || last) {
      r->train_loss = sum / count;
      double vloss = NAN;
      int save = last || t - last_ckpt >= s->checkpoint_seconds;
      if (save) {
        st = validate(dec, s, &val, &vloss, err);
        r->val_loss = vloss;
      }
      run_log_row(&log, "%lld,%.1f,%.6g,%.6g,%.4g", (long long)step, t - t0, r->train_loss, vloss,
                  (double)nbrdf_adam_lr(model_fit_adam(fit, 1), 0));
      sum = 0.0, count = 0;
      if (save) {
        st = train_checkpoint_save(ckpt, dec, fit, lat, data.n_brdfs, &data, err);
        if (!st) st = model_decoder_save(dec, dec_path, NULL, err);
        last_ckpt = now_s();
      }
    }
  }
  r->steps_done = step;
  r->finished = !st && step >= s->steps;
  if (!st && !r->finished)
    st = nbrdf_fail(err, NBRDF_ERR_CANCELLED,
                    "train decoder: stopped at step %lld of %lld "
                    "(checkpointed; run the same command to resume)",
                    (long long)step, (long long)s->steps);
  run_log_close(&log);
  train_energy_destroy(energy);
  model_fit_destroy(fit);
  model_decoder_destroy(dec);
  free(lat);
  free(weight);
  train_samples_free(&val);
  train_samples_free(&data);
  return st;
}
