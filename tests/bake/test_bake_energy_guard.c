/* The held-out check's energy guard (bake_energy_check.h) and the energy term of the
 * specialised decoder's fine-tune (bake_fit.h):
 * - the decision on synthetic figures: above max(1.01, fast's + margin) is energy creation,
 *   NaN too, a fit without figures (an old fit file) gets no verdict;
 * - end to end with the shipped model on a constant clearcoat of alpha1 0.001 (below the
 *   trained 0.01, which the fitting levels take as given): with the energy term off the
 *   specialised decoder creates energy (hundreds, measured) and the bake falls back to fast
 *   with a warning naming the figures and the header saying why; --no-fallback keeps the
 *   texture and still warns; with the default energy term it stays below 1.01 and keeps most
 *   of its lobe gain over fast; an ordinary tuple (alpha1 0.05) never trips the guard;
 * - the fit's objective (data term + energy term) against central finite differences in the
 *   latents and the decoder weights, the hinge held active. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_accuracy.h"
#include "bake/bake_audit.h"
#include "bake/bake_energy_check.h"
#include "bake/bake_fit.h"
#include "bake/bake_truth.h"
#include "model/autodecoder.h"
#include "model/bundle.h"
#include "nbrdf/bake.h"
#include "testing.h"
#include "texture/latent_exr.h"
#include "train/energy_reference.h"

static void test_decision(void) {
  CHECK(bake_energy_limit(0.7) == BAKE_AUDIT_LIMIT);
  CHECK_REL(bake_energy_limit(1.2), 1.2 + BAKE_ENERGY_MARGIN, 1e-12, 0.0);
  CHECK(!bake_energy_creates(1.005, 0.7));
  CHECK(bake_energy_creates(1.02, 0.7));
  /* Fast above the limit itself: the level may match it (falling back removes nothing). */
  CHECK(!bake_energy_creates(1.2 + 0.5 * BAKE_ENERGY_MARGIN, 1.2));
  CHECK(bake_energy_creates(1.2 + 2.0 * BAKE_ENERGY_MARGIN, 1.2));
  CHECK(bake_energy_creates(NAN, 0.7));

  bake_fit_result r;
  memset(&r, 0, sizeof r);
  r.heldout = 4, r.heldout_error = 0.05, r.heldout_error_fast = 0.17;
  r.albedo_tuples = 5, r.albedo_max = 16.7, r.albedo_max_fast = 0.74;
  CHECK(bake_fit_creates_energy(&r) && bake_fit_worse_than_fast(&r));
  char m[768];
  bake_fit_worse_message(&r, NBRDF_BAKE_SPECIALISED, m, sizeof m);
  /* Only the energy: its lobe error is better than fast's. */
  CHECK_MSG(!strstr(m, "lobe error") && strstr(m, "specialised decoder creates energy") &&
                strstr(m, "16.700") && strstr(m, "1.010") && strstr(m, "0.740") &&
                strstr(m, "5 fitted and held-out"),
            "%s", m);
  r.heldout_error = 0.2; /* both */
  bake_fit_worse_message(&r, NBRDF_BAKE_SPECIALISED, m, sizeof m);
  CHECK_MSG(strstr(m, "lobe error (20.00 %)") && strstr(m, "; the specialised decoder creates"),
            "%s", m);
  r.heldout_error = 0.05, r.albedo_max = 0.9;
  CHECK(!bake_fit_creates_energy(&r) && !bake_fit_worse_than_fast(&r));
  /* No figures (a fit file from before the guard): no verdict. */
  r.albedo_max = 16.7, r.albedo_tuples = 0;
  CHECK(!bake_fit_creates_energy(&r) && !bake_fit_worse_than_fast(&r));
}

static nbrdf_model *shipped;

/* The bench's clearcoat (bench/sharp_alpha.sh): eta 1.5 over a conductor alpha2 0.3, r0 0.9,
 * no slab. */
static nbrdf_bake_inputs coat(float a1) {
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA1], a1);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ETA], 1.5f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA2], 0.3f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_R0], 0.9f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALBEDO], 0.0f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_SIGMA_T], 0.0f);
  return in;
}

typedef struct warnings {
  char text[2048];
  int n;
} warnings;

static void collect(void *user, const char *message) {
  warnings *w = user;
  size_t len = strlen(w->text);
  snprintf(w->text + len, sizeof w->text - len, "%s\n", message);
  w->n++;
}

static void accuracy_of(const char *file, char *buf, size_t cap) {
  nbrdf_error e, *err = &e;
  texture_latent_reader *r = NULL;
  buf[0] = '\0';
  CHECK_OK(texture_latent_reader_open(&r, file, err), err);
  if (!r) return;
  const texture_latent_info *info = texture_latent_reader_info(r);
  snprintf(buf, cap, "%s", info->accuracy ? info->accuracy : "");
  texture_latent_reader_close(r);
}

static nbrdf_bake_options options(warnings *w) {
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.mip_levels = 1, o.energy_audit = 0, o.seed = 1;
  o.accuracy = NBRDF_BAKE_SPECIALISED, o.budget = 4.0;
  o.warning = collect, o.user = w;
  return o;
}

static void test_falls_back(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = coat(0.001f);
  warnings w = {{0}, 0};
  nbrdf_bake_options o = options(&w);
  o.fit_energy = -1.0; /* the fine-tune as before its energy term: the blow-up to catch */
  nbrdf_bake_report rep;
  const char *out = testing_path("off.exr");
  CHECK_OK(nbrdf_bake(shipped, &in, &o, out, &rep, err), err);
  CHECK_MSG(rep.fit_albedo_tuples >= 1 && rep.fit_max_albedo > 1.5 * BAKE_AUDIT_LIMIT &&
                rep.fit_max_albedo_fast < BAKE_AUDIT_LIMIT,
            "%zu tuples, level %g, fast %g: no blow-up to catch?", rep.fit_albedo_tuples,
            rep.fit_max_albedo, rep.fit_max_albedo_fast);
  CHECK(rep.creates_energy && rep.fell_back && rep.accuracy == NBRDF_BAKE_FAST &&
        rep.requested == NBRDF_BAKE_SPECIALISED);
  /* The lobe error alone would have kept it: the guard is what falls back. */
  CHECK_MSG(rep.heldout_error < rep.heldout_error_fast, "%g vs fast %g", rep.heldout_error,
            rep.heldout_error_fast);
  char figure[32];
  snprintf(figure, sizeof figure, "%.3f", rep.fit_max_albedo);
  CHECK_MSG(strstr(w.text, "specialised decoder creates energy") && strstr(w.text, figure) &&
                strstr(w.text, "baked at fast instead") && !strstr(w.text, "lobe error ("),
            "%s", w.text);
  char acc[1024];
  accuracy_of(out, acc, sizeof acc);
  CHECK_MSG(strstr(acc, "level=fast") && strstr(acc, "fellBack=1") &&
                strstr(acc, "fellBackFor=energy") && strstr(acc, "maxAlbedoFit="),
            "%s", acc);

  /* --no-fallback: the level's texture, the warning still said. */
  memset(&w, 0, sizeof w);
  o.no_fallback = 1;
  CHECK_OK(nbrdf_bake(shipped, &in, &o, testing_path("kept.exr"), &rep, err), err);
  CHECK(rep.creates_energy && !rep.fell_back && rep.accuracy == NBRDF_BAKE_SPECIALISED);
  CHECK_MSG(strstr(w.text, "specialised decoder creates energy") &&
                !strstr(w.text, "baked at fast"),
            "%s", w.text);
}

static void test_energy_term(void) {
  nbrdf_error e, *err = &e;
  warnings w = {{0}, 0};
  nbrdf_bake_options o = options(&w);
  nbrdf_bake_report rep;
  /* The default fine-tune at alpha1 0.001: below the limit, the lobe gain kept. */
  nbrdf_bake_inputs in = coat(0.001f);
  CHECK_OK(nbrdf_bake(shipped, &in, &o, testing_path("on.exr"), &rep, err), err);
  CHECK_MSG(!rep.creates_energy && !rep.fell_back && rep.fit_max_albedo <= BAKE_AUDIT_LIMIT &&
                rep.fit_max_albedo > 0.3,
            "albedo %g (fast %g), fell back %d: %s", rep.fit_max_albedo, rep.fit_max_albedo_fast,
            rep.fell_back, w.text);
  CHECK_MSG(rep.heldout_error < 0.75 * rep.heldout_error_fast,
            "held-out %g against fast's %g: the energy term lost the lobe gain", rep.heldout_error,
            rep.heldout_error_fast);
  CHECK_MSG(!strstr(w.text, "creates energy"), "%s", w.text);
  /* An ordinary tuple inside the trained range, the energy term off: nothing to catch. */
  memset(&w, 0, sizeof w);
  o.fit_energy = -1.0;
  in = coat(0.05f);
  CHECK_OK(nbrdf_bake(shipped, &in, &o, testing_path("ordinary.exr"), &rep, err), err);
  CHECK_MSG(rep.fit_albedo_tuples >= 1 && !rep.creates_energy && !rep.fell_back &&
                rep.fit_max_albedo < BAKE_AUDIT_LIMIT,
            "albedo %g (fast %g), fell back %d", rep.fit_max_albedo, rep.fit_max_albedo_fast,
            rep.fell_back);
  CHECK_MSG(!strstr(w.text, "creates energy"), "%s", w.text);
}

/* The fit's objective at `step` (what the trainer minimises). */
static double objective(model_fit *fit, const model_samples *ms, train_energy *en, const float *z,
                        int64_t step) {
  nbrdf_error e = {0};
  double loss = NAN;
  CHECK_OK(bake_fit_step(fit, ms, en, z, step, &loss, &e), &e);
  return loss;
}

/* Central differences of the objective against analytic gradient entries x[k], every
 * stride-th: the count of entries off by more than 3 % (plus 1 % of the largest). */
typedef struct fd_args {
  model_fit *fit;
  const model_samples *ms;
  train_energy *en;
  float *z;
  int64_t step;
  float h;
} fd_args;

static int fd_mismatches(const fd_args *a, float *x, size_t n, size_t stride, const float *g,
                         double gmax, const char *what) {
  int bad = 0;
  for (size_t k = 0; k < n; k += stride) {
    float keep = x[k];
    x[k] = keep + a->h;
    double up = objective(a->fit, a->ms, a->en, a->z, a->step);
    x[k] = keep - a->h;
    double down = objective(a->fit, a->ms, a->en, a->z, a->step);
    x[k] = keep;
    double num = (up - down) / (2.0 * a->h);
    if (fabs(num - g[k]) > 0.03 * fabs(num) + 0.01 * gmax) {
      bad++;
      printf("%s %zu: analytic %g numeric %g\n", what, k, g[k], num);
    }
  }
  return bad;
}

static void test_gradient(void) {
  nbrdf_error e, *err = &e;
  enum { N = 2, D = 8 };
  model_decoder_config cfg;
  CHECK_OK(model_decoder_preset("small", D, &cfg, err), err);
  model_decoder *dec = NULL;
  CHECK_OK(model_decoder_create(&cfg, 21u, &dec, err), err);
  if (!dec) return;
  /* Two tuples' ground truth, a few directions (the gradient does not care how many). */
  bake_tuple t[N] = {{{0.001f, 1.5f, 0.3f, 0.9f, 0.0f, 0.0f}},
                     {{0.2f, 1.3f, 0.1f, 0.5f, 0.5f, 1.0f}}};
  bake_truth_settings ts = {2, 16, 8, 64, 8, 16, 3u, NULL, 0.0, 0.0, NULL};
  train_samples samples = {0};
  CHECK_OK(bake_truth_samples(t, N, &ts, &samples, err), err);
  model_samples ms = train_samples_view(&samples);
  float z[N * D];
  for (int k = 0; k < N * D; k++)
    z[k] = (float)(0.8 * sin(1.7 * k + 0.3));
  /* The untrained decoder decodes ~0: its output bias (the last parameter) raised so that
   * every albedo is far above its ceiling (<= 1) and the hinge is active on both sides of
   * every difference below. */
  float *w = nn_params(dec->nn);
  const size_t np = nn_param_count(dec->nn);
  w[np - 1] += 3.0f;
  model_fit_options fo = MODEL_FIT_OPTIONS_DEFAULT;
  fo.rows_per_brdf = 32, fo.lr_weights = 5e-4f, fo.seed = 9u;
  model_fit *fit = NULL;
  train_energy *en = NULL;
  CHECK_OK(model_fit_create(dec, N, z, &fo, &fit, err), err);
  CHECK_OK(bake_fit_energy_create(dec, &samples, 1.0f, 4u, &en, err), err);
  if (!fit || !en) goto done;
  const int64_t step = 2 * BAKE_FIT_ENERGY_EVERY; /* a step that applies the energy term */
  double data = objective(fit, &ms, NULL, z, step), all = objective(fit, &ms, en, z, step);
  CHECK_MSG(all > data + 0.5, "data %g, with energy %g: the hinge is not active", data, all);
  float *gl = malloc(sizeof(float) * N * D), *gw = malloc(sizeof(float) * np);
  (void)objective(fit, &ms, en, z, step);
  memcpy(gl, model_fit_grad_latent(fit), sizeof(float) * N * D);
  memcpy(gw, model_fit_grad_weights(fit), sizeof(float) * np);
  const float h = 1e-2f;
  double gmax = 0.0, wmax = 0.0;
  for (int k = 0; k < N * D; k++)
    gmax = fmax(gmax, fabs(gl[k]));
  for (size_t k = 0; k < np; k++)
    wmax = fmax(wmax, fabs(gw[k]));
  CHECK(gmax > 0.0 && wmax > 0.0);
  fd_args fa = {fit, &ms, en, z, step, h};
  CHECK(fd_mismatches(&fa, z, (size_t)(N * D), 1, gl, gmax, "latent") == 0);
  CHECK(fd_mismatches(&fa, w, np, 53, gw, wmax, "weight") == 0);
  free(gl), free(gw);
done:
  train_energy_destroy(en);
  model_fit_destroy(fit);
  train_samples_free(&samples);
  model_decoder_destroy(dec);
}

int main(void) {
  nbrdf_error e, *err = &e;
  RUN(test_decision);
  RUN(test_gradient);
  char bundle[1024];
  snprintf(bundle, sizeof bundle, "%s/models/default", testing_source_dir());
  CHECK_OK(nbrdf_model_load(bundle, &shipped, err), err);
  if (shipped) {
    RUN(test_falls_back);
    RUN(test_energy_term);
  }
  nbrdf_model_destroy(shipped);
  return testing_finish();
}
