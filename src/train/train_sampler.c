#include "train/train_sampler.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/progress.h"
#include "core/rng.h"
#include "model/proxy.h"
#include "train/checkpoint.h"
#include "train/epoch_shuffle.h"

/* The fixed wide proposal the expectations are estimated with. */
#define Q0_SIGMA 0.25
#define Q0_W 0.5
#define LOG_SIGMA_LO (-6.9) /* σ = 0.001 */
#define LOG_SIGMA_HI 0.7    /* σ = 2 */

typedef struct latent_samples {
  int n;
  vec3 *wi, *wo;
  double *weight; /* f cos θo / q0, normalised to sum 1 per latent */
  double *lambert, *pg;
} latent_samples;

/* Cross-entropy −Σ weight log((1 − w) pg + w lambert) and its best w for the
 * current pg (convex in w: bisection on the derivative). */
static double best_w(const latent_samples *ls, double *w_out) {
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 40; it++) {
    double w = 0.5 * (lo + hi), d = 0.0;
    for (int j = 0; j < ls->n; j++) {
      double q = (1.0 - w) * ls->pg[j] + w * ls->lambert[j];
      if (ls->weight[j] > 0) d -= ls->weight[j] * (ls->lambert[j] - ls->pg[j]) / fmax(q, 1e-300);
    }
    if (d > 0)
      hi = w;
    else
      lo = w;
  }
  double w = 0.5 * (lo + hi), ce = 0.0;
  for (int j = 0; j < ls->n; j++)
    if (ls->weight[j] > 0)
      ce -= ls->weight[j] * log(fmax((1.0 - w) * ls->pg[j] + w * ls->lambert[j], 1e-300));
  *w_out = w;
  return ce;
}

static double ce_at(latent_samples *ls, double log_sigma, double *w) {
  double sigma = exp(log_sigma);
  for (int j = 0; j < ls->n; j++)
    ls->pg[j] = model_proxy_gaussian_pdf(sigma, ls->wi[j], ls->wo[j]);
  return best_w(ls, w);
}

/* Golden-section search over log σ (the cross-entropy is unimodal in σ for a
 * single-lobed target; for others this finds a local optimum). */
static double fit_one(latent_samples *ls, double *sigma, double *w) {
  const double g = 0.6180339887498949;
  double a = LOG_SIGMA_LO, b = LOG_SIGMA_HI, c = b - g * (b - a), d = a + g * (b - a), wc, wd;
  double fc = ce_at(ls, c, &wc), fd = ce_at(ls, d, &wd);
  for (int it = 0; it < 24; it++) {
    if (fc < fd)
      b = d, d = c, fd = fc, wd = wc, c = b - g * (b - a), fc = ce_at(ls, c, &wc);
    else
      a = c, c = d, fc = fd, wc = wd, d = a + g * (b - a), fd = ce_at(ls, d, &wd);
  }
  *sigma = exp(fc < fd ? c : d);
  *w = fc < fd ? wc : wd;
  return fc < fd ? fc : fd;
}

nbrdf_status train_sampler_targets(model_decoder *dec, size_t n, const float *latents,
                                   const train_sampler_settings *s, float *sigma, float *w,
                                   double *mean_ce_fit, double *mean_ce_cosine, nbrdf_error *err) {
  int m = s->incident * s->outgoing, D = dec->cfg.latent_dim;
  latent_samples ls = {m,
                       malloc((size_t)m * sizeof(vec3)),
                       malloc((size_t)m * sizeof(vec3)),
                       malloc((size_t)m * sizeof(double)),
                       malloc((size_t)m * sizeof(double)),
                       malloc((size_t)m * sizeof(double))};
  float *wi = malloc(6 * (size_t)m * sizeof *wi), *lat = malloc((size_t)m * D * sizeof *lat);
  float *f = malloc((size_t)m * sizeof *f);
  double *q0 = malloc((size_t)m * sizeof *q0);
  model_runner run = {0};
  nbrdf_status st = ls.wi && ls.wo && ls.weight && ls.lambert && ls.pg && wi && lat && f && q0
                        ? model_runner_create(dec->nn, 4096, NBRDF_NN_INFER, &run, err)
                        : core_fail(err, NBRDF_ERR_MEMORY, "sampler targets: out of memory");
  double sum_fit = 0.0, sum_cos = 0.0;
  for (size_t b = 0; b < n && !st; b++) {
    core_rng rng;
    core_rng_init(&rng, s->seed, b);
    /* Directions: stratified θi, ωo from the wide proposal. */
    for (int i = 0; i < s->incident; i++) {
      double th = (i + core_rng_uniform(&rng)) / s->incident * (80.0 * M_PI / 180.0);
      vec3 v = v3(sin(th), 0.0, cos(th));
      for (int k = 0; k < s->outgoing; k++) {
        int j = i * s->outgoing + k;
        vec3 o;
        double pdf = 0.0;
        while (!model_proxy_sample(Q0_SIGMA, Q0_W, v, core_rng_uniform(&rng),
                                   core_rng_uniform(&rng), core_rng_uniform(&rng), &o, &pdf))
          ;
        ls.wi[j] = v, ls.wo[j] = o, q0[j] = pdf;
        wi[3 * j] = (float)v.x, wi[3 * j + 1] = (float)v.y, wi[3 * j + 2] = (float)v.z;
        wi[3 * m + 3 * j] = (float)o.x, wi[3 * m + 3 * j + 1] = (float)o.y;
        wi[3 * m + 3 * j + 2] = (float)o.z;
        memcpy(lat + (size_t)j * D, latents + b * D, (size_t)D * sizeof *lat);
      }
    }
    st = model_decoder_eval(dec, &run, (size_t)m, 1, lat, wi, wi + 3 * m, f, err);
    if (st) break;
    /* Normalise per incident direction, so every ωi counts the same (GNDF average). */
    double total = 0.0;
    for (int i = 0; i < s->incident; i++) {
      double sum = 0.0;
      for (int k = 0; k < s->outgoing; k++) {
        int j = i * s->outgoing + k;
        ls.weight[j] = (double)f[j] * ls.wo[j].z / q0[j];
        ls.lambert[j] = ls.wo[j].z / M_PI;
        sum += ls.weight[j];
      }
      for (int k = 0; k < s->outgoing; k++)
        ls.weight[i * s->outgoing + k] = sum > 0 ? ls.weight[i * s->outgoing + k] / sum : 0.0;
      total += sum > 0;
    }
    for (int j = 0; j < m; j++)
      ls.weight[j] = total > 0 ? ls.weight[j] / total : 1.0 / m;
    double sg, ww;
    sum_fit += fit_one(&ls, &sg, &ww);
    for (int j = 0; j < m; j++)
      sum_cos -= ls.weight[j] * log(ls.lambert[j]);
    sigma[b] = (float)sg, w[b] = (float)ww;
    if (s->progress && s->progress(s->user, "sampler: targets", (double)(b + 1), (double)n))
      st = core_fail(err, NBRDF_ERR_CANCELLED, "train sampler: cancelled");
  }
  if (mean_ce_fit) *mean_ce_fit = sum_fit / (double)n;
  if (mean_ce_cosine) *mean_ce_cosine = sum_cos / (double)n;
  model_runner_destroy(&run);
  free(ls.wi), free(ls.wo), free(ls.weight), free(ls.lambert), free(ls.pg);
  free(wi), free(lat), free(f), free(q0);
  return st;
}

/* The raw outputs that give (σ, w) through model_sampler_transform. */
static void raw_outputs(float sigma, float w, float o[2]) {
  double s = fmax((double)sigma - MODEL_PROXY_SIGMA_MIN, 1e-6);
  double ww = fmin(fmax((double)w, 1e-4), 1.0 - 1e-4);
  o[0] = (float)(s > 30 ? s : log(expm1(s)));
  o[1] = (float)log(ww / (1.0 - ww));
}

/* The network's regression as a fit of the trainer (train/trainer.h): one
 * batch of latents per step, shuffled per epoch (train/epoch_shuffle.h). */
typedef struct sampler_run {
  model_sampler *net;
  const float *latents, *target;
  size_t n, D, B;
  int64_t steps_per_epoch;
  train_epoch_shuffle shuffle;
  model_runner run;
  float *dy, *grad;
} sampler_run;

static nbrdf_status gradient(void *user, int64_t step, double *loss, nbrdf_error *err) {
  sampler_run *t = user;
  const size_t *idx = train_epoch_shuffle_get(&t->shuffle, (uint64_t)(step / t->steps_per_epoch));
  size_t D = t->D, k0, m = trainer_epoch_batch(step, t->steps_per_epoch, t->n, t->B, &k0);
  for (size_t r0 = 0; r0 < m; r0++)
    memcpy(t->run.x + r0 * D, t->latents + idx[k0 + r0] * D, D * sizeof(float));
  nbrdf_status st = nn_forward(t->net->nn, t->run.ws, t->run.x, (int)m, t->run.y, err);
  double sq = 0.0;
  for (size_t r0 = 0; r0 < 2 * m && !st; r0++) {
    t->dy[r0] = (t->run.y[r0] - t->target[2 * idx[k0 + r0 / 2] + r0 % 2]) / (float)m;
    sq += (double)t->dy[r0] * t->dy[r0];
  }
  *loss = 0.5 * sq * (double)m; /* ½ Σ e² / m, the regression's loss */
  if (!st) memset(t->grad, 0, nn_param_count(t->net->nn) * sizeof *t->grad);
  if (!st) st = nn_backward(t->net->nn, t->run.ws, t->dy, NULL, t->grad, err);
  return st;
}

static void run_options(const sampler_run *t, model_decoder *dec, const train_sampler_settings *s,
                        char *out, size_t size) {
  char num[32];
  out[0] = '\0';
  trainer_option(out, size, "latent-dim", "%zu", t->D);
  trainer_option(out, size, "incident", "%d", s->incident);
  trainer_option(out, size, "outgoing", "%d", s->outgoing);
  trainer_option(out, size, "epochs", "%d", s->epochs); /* the schedule depends on it */
  trainer_option(out, size, "batch", "%d", s->batch);
  trainer_option(out, size, "lr", "%s", trainer_float_text(s->lr, num));
  trainer_option(out, size, "seed", "%llu", (unsigned long long)s->seed);
  trainer_option(out, size, "latents", "%zu, %016llx", t->n,
                 (unsigned long long)train_hash_floats(TRAIN_HASH_START, t->latents, t->n * t->D));
  trainer_option(out, size, "decoder weights", "%016llx",
                 (unsigned long long)train_hash_floats(TRAIN_HASH_START, nn_params_const(dec->nn),
                                                       nn_param_count(dec->nn)));
}

nbrdf_status train_sampler_fit(model_decoder *dec, size_t n, const float *latents,
                               const train_sampler_settings *s, model_sampler **out,
                               train_sampler_result *r, nbrdf_error *err) {
  memset(r, 0, sizeof *r);
  *out = NULL;
  size_t D = (size_t)dec->cfg.latent_dim, B = (size_t)s->batch;
  float *sigma = malloc(n * sizeof *sigma), *w = malloc(n * sizeof *w);
  float *target = malloc(2 * n * sizeof *target);
  sampler_run t = {.latents = latents, .target = target, .n = n, .D = D, .B = B};
  t.steps_per_epoch = (int64_t)((n + B - 1) / B);
  t.dy = malloc(2 * B * sizeof *t.dy);
  int shuffle_ok = train_epoch_shuffle_init(&t.shuffle, n, s->seed, 0x73616d70u);
  nbrdf_status st = sigma && w && target && t.dy && shuffle_ok
                        ? NBRDF_OK
                        : core_fail(err, NBRDF_ERR_MEMORY, "train sampler: out of memory");
  /* The targets are a function of the decoder and the latents: a resumed run
   * computes them again (seconds) rather than checkpointing them. */
  if (!st)
    st = train_sampler_targets(dec, n, latents, s, sigma, w, &r->mean_ce_fit, &r->mean_ce_cosine,
                               err);
  for (size_t b = 0; b < n && !st; b++)
    raw_outputs(sigma[b], w[b], target + 2 * b);
  if (!st) st = model_sampler_create("default", (int)D, s->seed, &t.net, err);
  if (!st) st = model_runner_create(t.net->nn, (int)B, NBRDF_NN_TRAIN, &t.run, err);
  if (!st && !(t.grad = malloc(nn_param_count(t.net->nn) * sizeof *t.grad)))
    st = core_fail(err, NBRDF_ERR_MEMORY, "train sampler: out of memory");
  if (!st) {
    char options[2048];
    run_options(&t, dec, s, options, sizeof options);
    trainer_group g = {"sampler.params",
                       "adam.m",
                       "adam.v",
                       nn_params(t.net->nn),
                       t.grad,
                       nn_param_count(t.net->nn),
                       s->lr,
                       (int)t.steps_per_epoch * (s->epochs / 3 > 0 ? s->epochs / 3 : 1),
                       0.3f};
    trainer_word words[3];
    train_epoch_shuffle_words(&t.shuffle, words);
    trainer_options to = TRAINER_OPTIONS_DEFAULT;
    trainer_options_epochs(&to, s->epochs, t.steps_per_epoch);
    to.stop_at_step = s->stop_at_step, to.max_seconds = s->max_seconds;
    to.checkpoint = s->checkpoint, to.checkpoint_seconds = s->checkpoint_seconds;
    to.format = "nbrdf-train-sampler-checkpoint", to.options = options;
    /* Asked after every batch, so Ctrl-C (the callback's answer) is heard
     * within one batch, not one epoch. */
    to.stage = "sampler: network", to.progress = s->progress, to.user = s->user;
    to.cancel = s->cancel;
    trainer_fit fit = {.user = &t, .gradient = gradient};
    trainer_result tr;
    st = trainer_run(&to, &fit, &g, 1, NULL, 0, words, 3, &tr, err);
    r->resumed_from = tr.resumed_from;
  }
  /* RMS error of the raw outputs over all latents. */
  double sq = 0.0;
  for (size_t k0 = 0; k0 < n && !st; k0 += B) {
    size_t m = n - k0 < B ? n - k0 : B;
    st = nn_forward(t.net->nn, t.run.ws, latents + k0 * D, (int)m, t.run.y, err);
    for (size_t r0 = 0; r0 < 2 * m && !st; r0++) {
      double e = t.run.y[r0] - target[2 * k0 + r0];
      sq += e * e;
    }
  }
  r->rms_o = sqrt(sq / (2.0 * (double)n));
  model_runner_destroy(&t.run);
  train_epoch_shuffle_free(&t.shuffle);
  free(sigma), free(w), free(target), free(t.dy), free(t.grad);
  if (st) {
    model_sampler_destroy(t.net);
    return st;
  }
  *out = t.net;
  return NBRDF_OK;
}
