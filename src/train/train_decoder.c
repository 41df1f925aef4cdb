#include "train/train_decoder.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error.h"
#include "core/rng.h"
#include "model/autodecoder.h"
#include "model/bundle_parts.h"
#include "train/checkpoint.h"
#include "train/dataset.h"
#include "train/energy_reference.h"
#include "train/params_latent.h"
#include "train/projection.h"
#include "train/samples.h"
#include "train/trainer.h"

/* Rows per forward/backward pass of a step (a step's 16 rows per BRDF go through in batches
 * of this many; the sum of their gradients is the step's). At 4096 rows a pass's buffers
 * (~5 KB a row for the medium decoder) spill out of L2, and OpenBLAS's SkylakeX kernels take
 * their small-matrix path (no packing, no zeroing of C) for the forward and input-gradient
 * GEMMs only below ~10^6 multiply-adds. Measured per step, medium preset, 16384 rows, one
 * thread: 43.5 ms at 4096, 40 at 512, 35 at 256, 32.5 at 128, 34.5 at 64 (SkylakeX kernels);
 * 60 -> 55.5 ms from 4096 to 128 with the Haswell kernels. */
#define TRAIN_DECODER_GEMM_ROWS 128

/* Held-out `rep` BRDFs (indices from TRAIN_VALIDATION_FIRST). */
static nbrdf_status make_validation(int n, train_samples *out, nbrdf_error *err) {
  memset(out, 0, sizeof *out);
  if (n <= 0) return NBRDF_OK;
  train_params *params = malloc((size_t)n * sizeof *params);
  if (!params) return core_fail(err, NBRDF_ERR_MEMORY, "validation: out of memory");
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
  if (!lat) return core_fail(err, NBRDF_ERR_MEMORY, "validation: out of memory");
  train_projection p = {s->loss, 256, 2e-2f, 100, 0.5f, s->seed, 300, 0};
  model_samples view = train_samples_view(val);
  nbrdf_status st = train_project_sets(dec, 1, &view, &lat, &p, NULL, NULL, err);
  model_fit_options o = MODEL_FIT_OPTIONS_DEFAULT;
  o.loss = s->loss;
  model_fit *fit = NULL;
  if (!st) st = model_fit_create(dec, val->n_brdfs, lat, &o, &fit, err);
  if (!st) st = model_fit_eval_loss(fit, &view, NULL, loss, err);
  model_fit_destroy(fit);
  free(lat);
  return st;
}

static nbrdf_status join(char *out, size_t size, const char *dir, const char *name,
                         nbrdf_error *err) {
  if ((size_t)snprintf(out, size, "%s/%s", dir, name) >= size)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: path too long", dir);
  return NBRDF_OK;
}

static void init_latents(float *lat, size_t n, uint64_t seed) {
  /* Small random latents (DeepSDF's N(0, 0.01²)) so that BRDFs start apart. */
  core_rng rng;
  core_rng_init(&rng, seed, 0x6c6174656e7473u);
  for (size_t k = 0; k < n; k++)
    lat[k] = (float)(0.01 * core_rng_normal(&rng));
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

/* The run's state the trainer's hooks work on. */
typedef struct decoder_run {
  const train_decoder_settings *s;
  model_decoder *dec;
  model_fit *fit;
  model_samples view;
  const train_samples *data, *val;
  const char *dec_path;
  train_energy *energy; /* NULL: no energy penalty */
  const float *lat;
  double sum, train_loss, val_loss;
  int count;
} decoder_run;

static nbrdf_status gradient(void *user, int64_t step, double *loss, nbrdf_error *err) {
  decoder_run *d = user;
  nbrdf_status st = model_fit_gradient(d->fit, &d->view, step, loss, err);
  double penalty = 0.0;
  if (!st) st = train_energy_add_fit(d->energy, d->fit, d->lat, step, &penalty, err);
  *loss += penalty;
  return st;
}

/* Log rows every log_every steps and at the end; validation at checkpoints. */
static nbrdf_status report(void *user, trainer *t, int64_t done, double loss, int flags,
                           nbrdf_error *err) {
  decoder_run *d = user;
  d->sum += loss, d->count++;
  if (done % d->s->log_every != 0 && !(flags & TRAINER_LAST)) return NBRDF_OK;
  d->train_loss = d->sum / d->count;
  double vloss = NAN, seconds = trainer_seconds(t);
  nbrdf_status st = NBRDF_OK;
  if (flags & TRAINER_SAVING) {
    st = validate(d->dec, d->s, d->val, &vloss, err);
    d->val_loss = vloss;
  }
  trainer_log(t, "%lld,%.1f,%.6g,%.6g,%.4g", (long long)done, seconds, d->train_loss, vloss,
              trainer_lr(t, 1));
  d->sum = 0.0, d->count = 0;
  return st;
}

static nbrdf_status save(void *user, nbrdf_error *err) {
  decoder_run *d = user;
  return model_decoder_save(d->dec, d->dec_path, NULL, err);
}

/* The options a resume must share: what shapes the steps, not their count. */
static nbrdf_status run_options(const decoder_run *d, char *out, size_t size, nbrdf_error *err) {
  const train_decoder_settings *s = d->s;
  char *spec = NULL, key[1024], num[32];
  nbrdf_status st = nn_spec_to_json(&d->dec->cfg.spec, &spec, err);
  if (st) return st;
  train_checkpoint_data_key(d->data, key, sizeof key);
  out[0] = '\0';
  trainer_option(out, size, "architecture", "%s", spec);
  trainer_option(out, size, "data", "%s", key);
  trainer_option(out, size, "rows-per-brdf", "%d", s->rows_per_brdf);
  trainer_option(out, size, "lr-weights", "%s", trainer_float_text(s->lr_weights, num));
  trainer_option(out, size, "lr-latent", "%s", trainer_float_text(s->lr_latent, num));
  trainer_option(out, size, "latent-l2", "%s", trainer_float_text(s->latent_l2, num));
  trainer_option(out, size, "decay-every", "%d", s->decay_every);
  trainer_option(out, size, "decay-gamma", "%s", trainer_float_text(s->decay_gamma, num));
  trainer_option(out, size, "loss", "%s", model_loss_name(s->loss));
  trainer_option(out, size, "brdf-weight", "%.17g", s->brdf_weight);
  trainer_option(out, size, "seed", "%llu", (unsigned long long)s->seed);
  if (s->init) trainer_option(out, size, "init-bundle", "%s", nbrdf_model_checksum(s->init));
  if (s->energy.lambda > 0) { /* absent when off: runs from before the penalty still match */
    trainer_option(out, size, "energy", "%s", trainer_float_text(s->energy.lambda, num));
    char angles[256] = "";
    for (int k = 0; k < s->energy.n_theta; k++)
      snprintf(angles + strlen(angles), sizeof angles - strlen(angles), "%s%g", k ? "," : "",
               s->energy.theta_deg[k]);
    trainer_option(out, size, "energy-angles", "%s", angles);
    trainer_option(out, size, "energy-brdfs", "%d", s->energy_brdfs);
    if (s->energy.floor_margin >= 0.0f) /* absent when off: earlier runs still match */
      trainer_option(out, size, "energy-floor", "%s",
                     trainer_float_text(s->energy.floor_margin, num));
  }
  free(spec);
  return NBRDF_OK;
}

static nbrdf_status require(const nn_st_reader *r, const char *k, const char *want,
                            const char *what, nbrdf_error *err) {
  const char *v = nn_st_metadata_get(r, k);
  if (v && !strcmp(v, want)) return NBRDF_OK;
  return core_fail(err, NBRDF_ERR_MISMATCH,
                   "%s: the checkpoint was made with another %s than this run's (start a new "
                   "run folder, or give the same settings)",
                   nn_st_label(r), what);
}

/* --init-bundle: the bundle's decoder weights (the run was created with its architecture)
 * and the latents it gives the data's BRDFs. */
static nbrdf_status init_from_bundle(const nbrdf_model *m, model_decoder *dec,
                                     const train_samples *data, float *lat, nbrdf_error *err) {
  memcpy(nn_params(dec->nn), nn_params(m->decoder->nn), nn_param_count(dec->nn) * sizeof(float));
  size_t D = (size_t)dec->cfg.latent_dim;
  nbrdf_status st = NBRDF_OK;
  for (size_t b = 0; b < data->n_brdfs && !st; b++)
    st = train_params_bundle_latent(m, &data->params[b], lat + b * D, err);
  return st;
}

/* Checkpoints from before nbrdf.options: architecture and data as they were
 * checked then (the other settings were not recorded). */
static nbrdf_status legacy(void *user, const nn_st_reader *r, int64_t *step, nbrdf_error *err) {
  decoder_run *d = user;
  char *spec = NULL, key[1024];
  train_checkpoint_data_key(d->data, key, sizeof key);
  nbrdf_status st = nn_spec_to_json(&d->dec->cfg.spec, &spec, err);
  if (!st) st = require(r, "nbrdf.spec", spec, "decoder architecture", err);
  if (!st) st = require(r, "nbrdf.data", key, "data sets", err);
  free(spec);
  const char *s = nn_st_metadata_get(r, "nbrdf.step");
  char *end = NULL;
  long long k = s ? strtoll(s, &end, 10) : -1;
  if (!st && (!s || *end || k < 0))
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: no valid nbrdf.step", nn_st_label(r));
  if (!st) *step = (int64_t)k;
  return st;
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
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "train decoder: steps, rows per BRDF, log interval and checkpoint "
                     "interval must be positive, the BRDF weight power in [0, 2]");
  if (mkdir(s->run_dir, 0777) != 0 && errno != EEXIST)
    return core_fail(err, NBRDF_ERR_IO, "%s: cannot create the run folder: %s", s->run_dir,
                     strerror(errno));

  train_samples data, val;
  memset(&val, 0, sizeof val);
  decoder_run d = {.s = s, .data = &data, .val = &val, .dec_path = dec_path};
  d.train_loss = d.val_loss = NAN;
  float *lat = NULL, *weight = NULL;
  char *options = malloc(16384);
  st = train_samples_load(s->n_data, s->data, &data, err);
  if (st) {
    free(options);
    return st;
  }
  st = make_validation(s->validation_brdfs, &val, err);
  /* A fine-tune keeps the bundle's architecture (the CLI refuses another). */
  model_decoder_config arch = s->init ? s->init->decoder->cfg : s->arch;
  size_t nl = data.n_brdfs * (size_t)arch.latent_dim;
  if (!st) st = model_decoder_create(&arch, s->seed, &d.dec, err);
  if (!st && (!(lat = malloc(nl * sizeof *lat)) || !options))
    st = core_fail(err, NBRDF_ERR_MEMORY, "train decoder: out of memory for latents");
  if (!st) {
    init_latents(lat, nl, s->seed);
    if (s->init) st = init_from_bundle(s->init, d.dec, &data, lat, err);
  }
  if (!st) {
    model_fit_options o = MODEL_FIT_OPTIONS_DEFAULT;
    o.loss = s->loss;
    o.rows_per_brdf = s->rows_per_brdf;
    o.lr_latent = s->lr_latent;
    o.lr_weights = s->lr_weights;
    o.latent_l2 = s->latent_l2;
    o.seed = s->seed;
    o.max_batch = TRAIN_DECODER_GEMM_ROWS;
    st = model_fit_create(d.dec, data.n_brdfs, lat, &o, &d.fit, err);
  }
  if (!st && s->brdf_weight != 0.0 && !(weight = brdf_weights(&data, s->brdf_weight)))
    st = core_fail(err, NBRDF_ERR_MEMORY, "train decoder: out of memory for BRDF weights");
  if (!st) st = train_energy_create(d.dec, &data, &s->energy, s->energy_brdfs, &d.energy, err);
  if (!st) st = run_options(&d, options, 16384, err);
  if (!st) {
    d.view = train_samples_view(&data);
    d.view.weight = weight;
    d.lat = lat;
    /* Latents first, then weights: the order Adam stepped them in before the trainer. */
    trainer_group groups[2] = {
        {"latents", "adam.latents.m", "adam.latents.v", lat, model_fit_grad_latent(d.fit), nl,
         s->lr_latent, s->decay_every, s->decay_gamma},
        {"decoder.params", "adam.weights.m", "adam.weights.v", nn_params(d.dec->nn),
         model_fit_grad_weights(d.fit), nn_param_count(d.dec->nn), s->lr_weights, s->decay_every,
         s->decay_gamma}};
    trainer_options to = TRAINER_OPTIONS_DEFAULT;
    to.steps = s->steps, to.stop_at_step = s->stop_at_step, to.max_seconds = s->max_seconds;
    to.checkpoint = ckpt, to.checkpoint_seconds = s->checkpoint_seconds;
    to.checkpoint_boundary = s->log_every;
    to.format = TRAIN_DECODER_CHECKPOINT_FORMAT, to.options = options;
    to.log_path = log_path, to.log_header = "step,seconds,train_loss,val_loss,lr";
    to.stage = "train decoder", to.progress = s->progress, to.user = s->user;
    to.cancel = s->cancel;
    trainer_fit fit = {&d, gradient, report, save, legacy};
    trainer_result tr;
    st = trainer_run(&to, &fit, groups, 2, NULL, 0, NULL, 0, &tr, err);
    r->steps_done = tr.steps_done, r->resumed_from = tr.resumed_from;
    r->finished = tr.finished, r->legacy_resume = tr.legacy_resume;
  }
  r->train_loss = d.train_loss, r->val_loss = d.val_loss;
  train_energy_destroy(d.energy);
  model_fit_destroy(d.fit);
  model_decoder_destroy(d.dec);
  free(lat);
  free(weight);
  free(options);
  train_samples_free(&val);
  train_samples_free(&data);
  return st;
}
