/* The bake's range check (bake_range.h) on an untrained random bundle: every parameter
 * outside the trained range is reported at once, before any network work, in the units the
 * user typed, with exact texel counts for maps this test makes (a texel once whatever its
 * channels, a constant once); REFUSE reports the same and then fails naming the first
 * texel. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "model/bundle.h"
#include "nbrdf/bake.h"
#include "testing.h"
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
  nbrdf_model_destroy(model);
  return testing_finish();
}
