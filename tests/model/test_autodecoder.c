/* A tiny end-to-end auto-decoder training on analytic GGX-conductor lobes
 * (decoder weights and one latent per BRDF learned together), then projection
 * of a held-out conductor into the trained, frozen decoder. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "core/vec3.h"
#include "model/autodecoder.h"
#include "testing.h"

enum { D = 8, PER = 1024, LOBE = 24 };

/* GGX conductor, height-correlated Smith, Schlick Fresnel (DESIGN.md), no cosine. */
static double ggx_conductor(double alpha, double r0, vec3 wi, vec3 wo) {
  vec3 h = v3_normalize(v3_add(wi, wo));
  double a2 = alpha * alpha, c2 = h.z * h.z, t = (a2 - 1.0) * c2 + 1.0;
  double d = a2 / (M_PI * t * t);
  double li = 0.5 * (-1.0 + sqrt(1.0 + a2 * (1.0 - wi.z * wi.z) / (wi.z * wi.z)));
  double lo = 0.5 * (-1.0 + sqrt(1.0 + a2 * (1.0 - wo.z * wo.z) / (wo.z * wo.z)));
  double g = 1.0 / (1.0 + li + lo);
  double f = r0 + (1.0 - r0) * pow(1.0 - v3_dot(wi, h), 5.0);
  return d * g * f / (4.0 * wi.z * wo.z);
}

static vec3 hemisphere(core_rng *rng) {
  double z = fmax(0.02, core_rng_uniform(rng));
  return v3_from_spherical(acos(z), 2 * M_PI * core_rng_uniform(rng));
}

static void put(float *dst, vec3 v) {
  dst[0] = (float)v.x, dst[1] = (float)v.y, dst[2] = (float)v.z;
}

/* PER samples of one conductor: half of ωo cosine-distributed, half uniform. */
static void sample_brdf(core_rng *rng, double alpha, double r0, float *wi, float *wo, float *f) {
  for (int k = 0; k < PER; k++) {
    vec3 a = hemisphere(rng), b = hemisphere(rng);
    if (k % 2)
      b = v3_from_spherical(asin(sqrt(core_rng_uniform(rng))), 2 * M_PI * core_rng_uniform(rng));
    if (b.z < 0.02) b = v3_normalize(v3(b.x, b.y, 0.02));
    put(wi + 3 * k, a);
    put(wo + 3 * k, b);
    f[k] = (float)ggx_conductor(alpha, r0, a, b);
  }
}

/* Lobe error of METRICS.md (relative L1 of f·cos θo images at θi ∈ {0, 30,
 * 60, 80}°), on LOBE² pixels to keep the test fast. */
static double lobe_error(const model_decoder *dec, const float *latent, double alpha, double r0) {
  nbrdf_error err = {0};
  model_runner run;
  if (model_runner_create(dec->nn, LOBE * LOBE, NBRDF_NN_INFER, &run, &err) != NBRDF_OK) return 1e9;
  static float wi[LOBE * LOBE * 3], wo[LOBE * LOBE * 3], lat[LOBE * LOBE * D], f[LOBE * LOBE];
  static double cosine[LOBE * LOBE];
  double diff = 0.0, ref = 0.0;
  const double thetas[4] = {0.0, 30.0, 60.0, 80.0};
  for (int t = 0; t < 4; t++) {
    vec3 w_i = v3_from_spherical(thetas[t] * M_PI / 180.0, 0.0);
    size_t n = 0;
    for (int py = 0; py < LOBE; py++) {
      for (int px = 0; px < LOBE; px++) {
        double x = 2.0 * (px + 0.5) / LOBE - 1.0, y = 2.0 * (py + 0.5) / LOBE - 1.0;
        if (x * x + y * y >= 1.0) continue;
        put(wi + 3 * n, w_i);
        put(wo + 3 * n, v3(x, y, sqrt(1.0 - x * x - y * y)));
        memcpy(lat + n * D, latent, D * sizeof(float));
        cosine[n] = sqrt(1.0 - x * x - y * y);
        n++;
      }
    }
    model_decoder_eval(dec, &run, n, 1, lat, wi, wo, f, &err);
    for (size_t k = 0; k < n; k++) {
      vec3 a = v3(wi[3 * k], wi[3 * k + 1], wi[3 * k + 2]),
           b = v3(wo[3 * k], wo[3 * k + 1], wo[3 * k + 2]);
      double truth = ggx_conductor(alpha, r0, v3_normalize(a), v3_normalize(b)) * cosine[k];
      diff += fabs(f[k] * cosine[k] - truth);
      ref += fabs(truth);
    }
  }
  model_runner_destroy(&run);
  return diff / ref;
}

/* `steps` steps of Adam on the engine's gradients (the loop src/train/trainer.h
 * runs, without its checkpoints); weights NULL when frozen. */
static nbrdf_status run_steps(model_fit *fit, const model_samples *s, const model_fit_options *o,
                              int decay_every, float *latents, size_t nl, float *weights, size_t nw,
                              int steps, nbrdf_error *err) {
  if (!fit) return NBRDF_OK;
  nn_adam_options ao = NBRDF_ADAM_OPTIONS_DEFAULT;
  ao.decay_every = decay_every, ao.decay_gamma = 0.5f;
  nn_adam *al = NULL, *aw = NULL;
  ao.lr = o->lr_latent;
  nbrdf_status st = nn_adam_create(nl, &ao, &al, err);
  ao.lr = o->lr_weights;
  if (!st && weights) st = nn_adam_create(nw, &ao, &aw, err);
  for (int k = 0; k < steps && !st; k++) {
    st = model_fit_gradient(fit, s, k, NULL, err);
    if (!st) st = nn_adam_step(al, latents, model_fit_grad_latent(fit), err);
    if (!st && aw) st = nn_adam_step(aw, weights, model_fit_grad_weights(fit), err);
  }
  nn_adam_destroy(al);
  nn_adam_destroy(aw);
  return st;
}

static void test_train_then_project(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  enum { NB = 16 };
  const double alphas[4] = {0.15, 0.25, 0.4, 0.6}, r0s[4] = {0.2, 0.45, 0.7, 0.95};
  float *wi = malloc(sizeof(float) * 3 * PER * NB), *wo = malloc(sizeof(float) * 3 * PER * NB);
  float *f = malloc(sizeof(float) * PER * NB), latents[NB * D];
  size_t offsets[NB + 1];
  core_rng rng;
  core_rng_init(&rng, 2022, 0);
  for (int b = 0; b < NB; b++) {
    offsets[b] = (size_t)b * PER;
    sample_brdf(&rng, alphas[b / 4], r0s[b % 4], wi + 3 * b * PER, wo + 3 * b * PER, f + b * PER);
  }
  offsets[NB] = (size_t)NB * PER;
  for (int i = 0; i < NB * D; i++)
    latents[i] = (float)(0.1 * core_rng_normal(&rng));

  model_decoder_config cfg;
  model_encoding enc = {MODEL_ENCODING_HALFDIFF, 0};
  CHECK_OK(model_decoder_config_make(D, enc, MODEL_OUTPUT_LOG1P, 32, 2, 1, &cfg, err), err);
  model_decoder *dec = NULL;
  CHECK_OK(model_decoder_create(&cfg, 1, &dec, err), err);
  model_fit_options o = MODEL_FIT_OPTIONS_DEFAULT;
  o.rows_per_brdf = 32;
  o.lr_weights = 1e-2f;
  o.lr_latent = 1e-2f;
  o.latent_l2 = 1e-4f;
  o.seed = 7;
  model_fit *fit = NULL;
  CHECK_OK(model_fit_create(dec, NB, latents, &o, &fit, err), err);
  model_samples s = {NB, offsets, wi, wo, f, NULL};
  double first = 0.0, last = 0.0;
  CHECK_OK(model_fit_eval_loss(fit, &s, NULL, &first, err), err);
  CHECK_OK(run_steps(fit, &s, &o, 333, latents, NB * D, nn_params(dec->nn), nn_param_count(dec->nn),
                     1000, err),
           err);
  CHECK_OK(model_fit_eval_loss(fit, &s, NULL, &last, err), err);
  printf("  auto-decoder: L1-log1p loss %.4f -> %.4f after 1000 steps\n", first, last);
  CHECK_MSG(last < first / 20.0, "loss fell only from %.4f to %.4f", first, last);
  model_fit_destroy(fit);

  /* Held-out conductor (inside the trained range, not a training node). */
  const double alpha = 0.32, r0 = 0.58;
  float hwi[3 * PER], hwo[3 * PER], hf[PER], z[D] = {0}, mean[D] = {0};
  size_t hoff[2] = {0, PER};
  sample_brdf(&rng, alpha, r0, hwi, hwo, hf);
  for (int b = 0; b < NB; b++)
    for (int j = 0; j < D; j++)
      mean[j] += latents[b * D + j] / NB;
  model_fit_options po = MODEL_FIT_OPTIONS_DEFAULT; /* decoder frozen */
  po.rows_per_brdf = 256;
  po.lr_latent = 2e-2f;
  po.seed = 8;
  model_fit *proj = NULL;
  CHECK_OK(model_fit_create(dec, 1, z, &po, &proj, err), err);
  model_samples hs = {1, hoff, hwi, hwo, hf, NULL};
  float before[64];
  size_t np = nn_param_count(dec->nn);
  memcpy(before, nn_params(dec->nn), sizeof before);
  CHECK_OK(run_steps(proj, &hs, &po, 0, z, D, NULL, 0, 300, err), err);
  model_fit_destroy(proj);
  CHECK(np > 64 && !memcmp(before, nn_params(dec->nn), sizeof before)); /* frozen */
  double e_proj = lobe_error(dec, z, alpha, r0), e_mean = lobe_error(dec, mean, alpha, r0);
  double e_train = lobe_error(dec, latents + 6 * D, alphas[1], r0s[2]);
  printf("  lobe error: projected held-out %.1f %%, mean latent %.1f %%, a training BRDF %.1f %%\n",
         100 * e_proj, 100 * e_mean, 100 * e_train);
  CHECK_MSG(e_proj < 0.4 * e_mean, "projection %.3f is not well below the mean latent %.3f", e_proj,
            e_mean);
  CHECK_MSG(e_proj < 0.12, "projected lobe error %.3f", e_proj);
  model_decoder_destroy(dec);
  free(wi), free(wo), free(f);
}

int main(void) {
  RUN(test_train_then_project);
  return testing_finish();
}
