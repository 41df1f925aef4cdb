/* The bake's range check (bake_range.h) on an untrained random bundle: every parameter
 * outside the trained range is reported at once, before any network work, in the units the
 * user typed, with exact texel counts for maps this test makes (a texel once whatever its
 * channels, a constant once); REFUSE reports the same and then fails naming the first
 * texel. The fitting levels take alpha1 and alpha2 down to NBRDF_GT_ALPHA_MIN as given: the
 * report says what each level does, and their held-out truth is that of the value given
 * (with the shipped model: its fast level's error tells the truths apart). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "model/bundle.h"
#include "nbrdf/bake.h"
#include "nbrdf/brdf.h"
#include "testing.h"
#include "texture/latent_exr.h"
#include "texture/oiio_shim.h"

static nbrdf_model *model;
static char tmp[512];

static const char *path(const char *name) {
  static char buf[4][640];
  static int k;
  k = (k + 1) % 4;
  snprintf(buf[k], sizeof buf[k], "%s/%s", tmp, name);
  return buf[k];
}

static void grid(nbrdf_base_kind kind, float lo[2], float hi[2]) {
  int n0, n1;
  const float *a0, *a1;
  nbrdf_model_base_grid(model, kind, &n0, &a0, &n1, &a1);
  lo[0] = a0[0], hi[0] = a0[n0 - 1], lo[1] = a1[0], hi[1] = a1[n1 - 1];
}

#define W 16
#define H 12
/* alpha1 in perceptual roughness: BELOW texels under the range, ABOVE over it. */
#define BELOW 7
#define ABOVE 3
/* r0 (RGB): texels with one, two or three channels over the range: R0_ABOVE texels. */
#define R0_ABOVE 4

static float r_lo, r_hi, r0_hi;

/* alpha1.exr: perceptual roughness, mid-range except BELOW texels from (5, 2) on at
 * 0.5 r_lo (the lowest 0.25 r_lo at (9, 7)) and ABOVE texels at 1.5 r_hi (the highest 2 r_hi).
 * r0.exr: mid-range except R0_ABOVE texels with 1, 2, 3 and 1 channels above the range. */
static void write_maps(void) {
  nbrdf_error e, *err = &e;
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  r_lo = sqrtf(lo[0]), r_hi = sqrtf(hi[0]);
  float a[W * H];
  for (int i = 0; i < W * H; i++)
    a[i] = 0.5f * (r_lo + r_hi);
  for (int k = 0; k < BELOW; k++)
    a[2 * W + 5 + k * 11] = 0.5f * r_lo;
  a[7 * W + 9] = 0.25f * r_lo;
  for (int k = 0; k < ABOVE; k++)
    a[10 * W + 2 + k] = 1.5f * r_hi;
  a[10 * W + 3] = 2.0f * r_hi;
  CHECK_OK(texture_image_write(path("alpha1.exr"), W, H, 1, a, NBRDF_PIXEL_FLOAT, err), err);
  grid(NBRDF_BASE_CONDUCTOR, lo, hi);
  r0_hi = hi[1];
  printf("  r0 trained up to %g: %s\n", (double)r0_hi,
         r0_hi < 1.0f ? "RGB texels above it" : "no r0 above it (not tested)");
  float r0[W * H * 3];
  for (int i = 0; i < W * H * 3; i++)
    r0[i] = 0.5f * (lo[1] + hi[1]);
  /* Above the grid but at most 1 (physical): only when the grid stops below 1. */
  float up = 0.5f * (hi[1] + 1.0f);
  static const int channels[R0_ABOVE] = {1, 2, 3, 1};
  for (int k = 0; k < R0_ABOVE && hi[1] < 1.0f; k++)
    for (int c = 0; c < channels[k]; c++)
      r0[(4 * W + 3 * k) * 3 + c] = up;
  CHECK_OK(texture_image_write(path("r0.exr"), W, H, 3, r0, NBRDF_PIXEL_FLOAT, err), err);
}

/* Mid-range constants, then alpha1 and r0 from the maps; eta a constant above the range,
 * sigma_t an RGB constant above it on two channels. Perceptual roughness. */
static nbrdf_bake_inputs inputs(void) {
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ETA], hi[1] + 1.0f);
  grid(NBRDF_BASE_CONDUCTOR, lo, hi);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA2], sqrtf(0.5f * (lo[0] + hi[0])));
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALBEDO], 0.8f);
  nbrdf_bake_param *s = &in.param[NBRDF_BAKE_SIGMA_T];
  s->channels = 3, s->value[0] = 7.0f, s->value[1] = 1.0f, s->value[2] = 9.0f;
  in.param[NBRDF_BAKE_ALPHA1].path = path("alpha1.exr");
  in.param[NBRDF_BAKE_R0].path = path("r0.exr");
  return in;
}

typedef struct seen {
  nbrdf_bake_range r[NBRDF_BAKE_PARAM_COUNT];
  int reports, progress_before, progress;
} seen;

static void on_range(void *user, const nbrdf_bake_range *r) {
  seen *s = user;
  if (r->param >= 0 && r->param < NBRDF_BAKE_PARAM_COUNT) s->r[r->param] = *r;
  s->reports++;
  s->progress_before += s->progress;
}

static int on_progress(void *user, const char *stage, double done, double total) {
  (void)stage, (void)done, (void)total;
  ((seen *)user)->progress++;
  return 0;
}

static void check_reports(const seen *s) {
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  int r0_out = r0_hi < 1.0f;
  CHECK_MSG(s->reports == 3 + r0_out, "%d reports", s->reports);
  CHECK(s->progress_before == 0); /* all of them before any work */
  const nbrdf_bake_range *a = &s->r[NBRDF_BAKE_ALPHA1];
  CHECK(!strcmp(a->name, "alpha1") && !strcmp(a->units, "perceptual roughness") && !a->constant);
  CHECK_MSG(a->below == BELOW + 1 && a->above == ABOVE, "below %zu above %zu", a->below, a->above);
  CHECK(a->min == (double)(0.25f * r_lo) && a->max == (double)(2.0f * r_hi));
  CHECK_NEAR(a->lo, r_lo, 1e-6);
  CHECK_NEAR(a->hi, r_hi, 1e-6);
  const nbrdf_bake_range *eta = &s->r[NBRDF_BAKE_ETA];
  CHECK(!strcmp(eta->units, "IOR") && eta->constant && eta->below == 0 && eta->above == 1);
  CHECK(eta->max == (double)(hi[1] + 1.0f) && eta->hi == (double)hi[1]);
  /* An RGB constant above on two channels is one texel. */
  const nbrdf_bake_range *st = &s->r[NBRDF_BAKE_SIGMA_T];
  CHECK(st->constant && st->above == 1 && st->max == 9.0 && st->hi == NBRDF_BAKE_SIGMA_T_MAX);
  CHECK(!strcmp(st->units, "optical depth"));
  /* r0: texels with 1, 2 or 3 channels above count once each. */
  if (r0_out) CHECK_MSG(s->r[NBRDF_BAKE_R0].above == R0_ABOVE, "%zu", s->r[NBRDF_BAKE_R0].above);
}

static void test_clamp(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = inputs();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.roughness = NBRDF_ROUGHNESS_PERCEPTUAL;
  o.mip_levels = 1, o.energy_audit = 0;
  seen s = {0};
  o.range_report = on_range, o.progress = on_progress, o.user = &s;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("clamp.exr"), NULL, err), err);
  check_reports(&s);
  CHECK(s.progress > 0 && s.r[NBRDF_BAKE_ALPHA1].policy == NBRDF_RANGE_CLAMP);
}

static void test_refuse(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = inputs();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.roughness = NBRDF_ROUGHNESS_PERCEPTUAL;
  o.range = NBRDF_RANGE_REFUSE;
  seen s = {0};
  o.range_report = on_range, o.progress = on_progress, o.user = &s;
  /* Every parameter reported, then the first refused value in the bake's order: the
   * constant eta at the first texel. */
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("refuse.exr"), NULL, err), NBRDF_ERR_ARGUMENT, err,
              "eta (constant)");
  check_reports(&s);
  CHECK(s.progress == 0 && s.r[NBRDF_BAKE_ETA].policy == NBRDF_RANGE_REFUSE);
  /* With the constants inside: the map's first texel outside, row by row. */
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ETA], 0.5f * (lo[1] + hi[1]));
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_SIGMA_T], 1.0f);
  in.param[NBRDF_BAKE_R0].path = NULL;
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_R0], 0.5f);
  memset(&s, 0, sizeof s);
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("refuse.exr"), NULL, err), NBRDF_ERR_ARGUMENT, err,
              "alpha1.exr: texel (5, 2), alpha1");
  CHECK(s.reports == 1 && s.r[NBRDF_BAKE_ALPHA1].below == BELOW + 1);
}

/* A constant scene with alpha1 `a1` (GGX alpha) and everything else inside the range. */
static nbrdf_bake_inputs constant_scene(float a1) {
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA1], a1);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ETA], 0.5f * (lo[1] + hi[1]));
  grid(NBRDF_BASE_CONDUCTOR, lo, hi);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA2], 0.5f * (lo[0] + hi[0]));
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_R0], 0.5f * (lo[1] + hi[1]));
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALBEDO], 0.5f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_SIGMA_T], 1.0f);
  return in;
}

/* The texture's header: sources and the accuracy attribute, into buffers. */
static void header(const char *file, char *sources, char *accuracy, size_t cap) {
  nbrdf_error e, *err = &e;
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, file, err), err);
  if (!r) return;
  const texture_latent_info *info = texture_latent_reader_info(r);
  snprintf(sources, cap, "%s", info->sources ? info->sources : "");
  snprintf(accuracy, cap, "%s", info->accuracy ? info->accuracy : "");
  texture_latent_reader_close(r);
}

/* SPECIALISED takes alpha1 = 0.002 (below the trained range) as given: nothing is clamped, the
 * header records 0.002, and the held-out error is measured against the truth of 0.002, not of
 * the trained minimum: the universal networks' latent is the same for 0.002 and for the
 * minimum (the base tables clamp), so with the same seed and streams fast's held-out error
 * differs only if the truth does. FAST clamps the same value and says so. */
static void test_fitting_levels(void) {
  nbrdf_error e, *err = &e;
  /* The shipped model: an untrained one decodes nothing, whose error is 1 against any truth. */
  nbrdf_model *random = model;
  char bundle[1024];
  snprintf(bundle, sizeof bundle, "%s/models/default", testing_source_dir());
  CHECK_OK(nbrdf_model_load(bundle, &model, err), err);
  if (!model) {
    model = random;
    return;
  }
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  CHECK_MSG(lo[0] > 0.002f, "the trained alpha1 starts at %g: nothing below it to test", lo[0]);
  nbrdf_bake_inputs given = constant_scene(0.002f), trained = constant_scene(lo[0]);
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.mip_levels = 1, o.energy_audit = 0, o.seed = 5;
  o.accuracy = NBRDF_BAKE_SPECIALISED, o.budget = 4.0, o.no_fallback = 1;
  seen s = {0};
  o.range_report = on_range, o.user = &s;
  nbrdf_bake_report a, b;
  CHECK_OK(nbrdf_bake(model, &given, &o, path("given.exr"), &a, err), err);
  CHECK_MSG(s.reports == 1, "%d range reports", s.reports);
  const nbrdf_bake_range *r = &s.r[NBRDF_BAKE_ALPHA1];
  CHECK(r->below == 1 && r->below_fit == 0 && r->min == (double)0.002f);
  CHECK(r->accuracy == NBRDF_BAKE_SPECIALISED && r->fit_lo == (double)(float)NBRDF_GT_ALPHA_MIN);
  char m[768];
  nbrdf_bake_range_message(r, m, sizeof m);
  CHECK_MSG(strstr(m, "0.002 is below") && strstr(m, "fast bakes it as") &&
                strstr(m, "specialised and compact fit it as given"),
            "%s", m);
  CHECK_MSG(a.clamped == 0, "%zu clamped", a.clamped);
  char sources[1024], accuracy[1024];
  header(path("given.exr"), sources, accuracy, sizeof sources);
  CHECK_MSG(strstr(sources, "alpha1=0.002"), "%s", sources);
  CHECK_MSG(strstr(accuracy, "level=specialised"), "%s", accuracy);
  CHECK_OK(nbrdf_bake(model, &trained, &o, path("trained.exr"), &b, err), err);
  CHECK(a.heldout_tuples == 1 && b.heldout_tuples == 1);
  CHECK_MSG(isfinite(a.heldout_error_fast) && isfinite(b.heldout_error_fast) &&
                fabs(a.heldout_error_fast - b.heldout_error_fast) >
                    1e-3 * fabs(b.heldout_error_fast),
            "fast's held-out error %g at alpha1 0.002, %g at %g: the same truth?",
            a.heldout_error_fast, b.heldout_error_fast, lo[0]);

  /* FAST clamps it (REFUSE refuses it); a fitting level under REFUSE takes it. */
  nbrdf_bake_options f = NBRDF_BAKE_OPTIONS_DEFAULT;
  f.mip_levels = 1, f.energy_audit = 0;
  memset(&s, 0, sizeof s);
  f.range_report = on_range, f.user = &s;
  CHECK_OK(nbrdf_bake(model, &given, &f, path("fast.exr"), &a, err), err);
  CHECK(a.clamped == 1 && s.r[NBRDF_BAKE_ALPHA1].accuracy == NBRDF_BAKE_FAST);
  nbrdf_bake_range_message(&s.r[NBRDF_BAKE_ALPHA1], m, sizeof m);
  CHECK_MSG(strstr(m, "0.002 is below") && strstr(m, "and will be baked as") &&
                strstr(m, "fit down to 0.001 as given"),
            "%s", m);
  f.range = NBRDF_RANGE_REFUSE;
  CHECK_FAILS(nbrdf_bake(model, &given, &f, path("fast.exr"), NULL, err), NBRDF_ERR_ARGUMENT, err,
              "alpha1 (constant) = 0.002");
  o.range = NBRDF_RANGE_REFUSE, o.accuracy = NBRDF_BAKE_FITTED, o.no_fallback = 0;
  CHECK_OK(nbrdf_bake(model, &given, &o, path("fitted.exr"), &a, err), err);
  /* Fitted, or fast after the held-out check: then clamped, as the report said. */
  CHECK_MSG(a.fell_back ? a.clamped == 1 : a.clamped == 0, "fell back %d, clamped %zu", a.fell_back,
            a.clamped);
  /* Below what the fitting levels take: refused under REFUSE, else fitted as that floor. */
  nbrdf_bake_inputs floor = constant_scene(0.0005f);
  CHECK_FAILS(nbrdf_bake(model, &floor, &o, path("floor.exr"), NULL, err), NBRDF_ERR_ARGUMENT, err,
              "alpha1 (constant) = 0.0005");
  nbrdf_model_destroy(model);
  model = random;
}

/* Without range_report, each parameter is one warning line (nbrdf_bake_range_message). */
static void collect(void *user, const char *message) {
  char *buf = user;
  size_t n = strlen(buf);
  snprintf(buf + n, 4096 - n, "%s\n", message);
}

static void test_messages(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = inputs();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.roughness = NBRDF_ROUGHNESS_PERCEPTUAL;
  o.mip_levels = 1, o.energy_audit = 0;
  char msgs[4096] = "";
  o.warning = collect, o.user = msgs;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("warn.exr"), NULL, err), err);
  char want[256];
  snprintf(want, sizeof want, "alpha1 (perceptual roughness): %d texels below %g (min %g)",
           BELOW + 1, (double)r_lo, (double)(0.25f * r_lo));
  CHECK_MSG(strstr(msgs, want) != NULL, "%s", msgs);
  CHECK_MSG(strstr(msgs, "sigma_t (optical depth): 9 is above 5 and will be baked as 5"), "%s",
            msgs);

  nbrdf_bake_range r = {.param = NBRDF_BAKE_ALPHA1,
                        .name = "alpha1",
                        .units = "perceptual roughness",
                        .below = 1204,
                        .min = 0.02,
                        .lo = 0.1,
                        .hi = 1.0,
                        .policy = NBRDF_RANGE_CLAMP};
  char m[512];
  CHECK_MSG(!strcmp(nbrdf_bake_range_message(&r, m, sizeof m),
                    "alpha1 (perceptual roughness): 1,204 texels below 0.1 (min 0.02) will be "
                    "baked as 0.1"),
            "%s", m);
  r.above = 1, r.max = 1.5, r.below = 1234567, r.policy = NBRDF_RANGE_REFUSE;
  CHECK_MSG(!strcmp(nbrdf_bake_range_message(&r, m, sizeof m),
                    "alpha1 (perceptual roughness): 1,234,567 texels below 0.1 (min 0.02; "
                    "trained range [0.1, 1]); 1 texel above 1 (max 1.5; trained range [0.1, 1])"),
            "%s", m);
  /* With what the fitting levels take (alpha 0.001, r 0.0316): per level. */
  r.above = 0, r.below = 1204, r.below_fit = 3, r.fit_lo = sqrt(0.001), r.min = 0.02;
  CHECK_MSG(!strcmp(nbrdf_bake_range_message(&r, m, sizeof m),
                    "alpha1 (perceptual roughness): 1,204 texels below 0.1 (min 0.02; trained range "
                    "[0.1, 1]; fitted, specialised and compact take down to 0.0316 as given)"),
            "%s", m);
  r.accuracy = NBRDF_BAKE_SPECIALISED;
  CHECK_MSG(!strcmp(nbrdf_bake_range_message(&r, m, sizeof m),
                    "alpha1 (perceptual roughness): 1,204 texels below 0.1 (min 0.02): fast bakes "
                    "them as 0.1; fitted, specialised and compact fit them as given, but 3 below "
                    "0.0316, the lowest they take, are refused"),
            "%s", m);
  r.policy = NBRDF_RANGE_CLAMP, r.accuracy = NBRDF_BAKE_AUTO;
  CHECK_MSG(!strcmp(nbrdf_bake_range_message(&r, m, sizeof m),
                    "alpha1 (perceptual roughness): 1,204 texels below 0.1 (min 0.02): fast bakes "
                    "them as 0.1; fitted, specialised and compact fit them as given, and 3 below "
                    "0.0316 as 0.0316"),
            "%s", m);
}

int main(void) {
  nbrdf_error e, *err = &e;
  snprintf(tmp, sizeof tmp, "%s", testing_tmpdir());
  CHECK_OK(model_bundle_init_random(path("bundle"), "range-test", 7, "small", err), err);
  CHECK_OK(nbrdf_model_load(path("bundle"), &model, err), err);
  if (!model) return testing_finish();
  write_maps();
  RUN(test_clamp);
  RUN(test_refuse);
  RUN(test_messages);
  RUN(test_fitting_levels);
  nbrdf_model_destroy(model);
  return testing_finish();
}
