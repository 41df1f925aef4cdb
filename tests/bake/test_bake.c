/* nbrdf_bake on an untrained random bundle: constant and map inputs give
 * the latents of the direct library computation (table look-up, layering,
 * sampler), mip levels average them, bad input fails naming the file (and
 * texel) and leaves no file, and the bytes are deterministic. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bake/bake_audit.h"
#include "model/audit_slopes.h"
#include "model/bundle.h"
#include "nbrdf/bake.h"
#include "testing.h"
#include "texture/latent_exr.h"
#include "texture/oiio_shim.h"
#include "texture/param_source.h"

static nbrdf_model *model;
static char tmp[512];

static const char *path(const char *name) {
  static char buf[4][640];
  static int k;
  k = (k + 1) % 4;
  snprintf(buf[k], sizeof buf[k], "%s/%s", tmp, name);
  return buf[k];
}

static int exists(const char *p) {
  struct stat sb;
  return stat(p, &sb) == 0;
}

/* No temporary files ("." + name + ".tmp") left in the folder. */
static int no_temporaries(void) {
  DIR *d = opendir(tmp);
  if (!d) return 0;
  int clean = 1;
  struct dirent *e;
  while ((e = readdir(d)))
    if (strstr(e->d_name, ".tmp")) clean = 0;
  closedir(d);
  return clean;
}

static void grid(nbrdf_base_kind kind, float lo[2], float hi[2]) {
  int n0, n1;
  const float *a0, *a1;
  nbrdf_model_base_grid(model, kind, &n0, &a0, &n1, &a1);
  lo[0] = a0[0], hi[0] = a0[n0 - 1], lo[1] = a1[0], hi[1] = a1[n1 - 1];
}

/* Mid-range constants for all six parameters. */
static nbrdf_bake_inputs constants(void) {
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA1], 0.3f * lo[0] + 0.7f * hi[0]);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ETA], 0.5f * (lo[1] + hi[1]));
  grid(NBRDF_BASE_CONDUCTOR, lo, hi);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA2], 0.5f * (lo[0] + hi[0]));
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_R0], 0.6f * lo[1] + 0.4f * hi[1]);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALBEDO], 0.8f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_SIGMA_T], 1.5f);
  return in;
}

/* The latent, sigma and w of one tuple, computed directly. */
static void direct(const float t[6], float *latent, float *sigma, float *w) {
  nbrdf_error e, *err = &e;
  int D = nbrdf_model_latent_dim(model);
  float *top = malloc(sizeof(float) * D * 2), *bottom = top + D;
  float a = t[0], b = t[1], c = t[2], d = t[3];
  CHECK_OK(nbrdf_model_base_latents(model, NBRDF_BASE_DIELECTRIC, 1, &a, &b, NBRDF_RANGE_REFUSE,
                                    top, NULL, err),
           err);
  CHECK_OK(nbrdf_model_base_latents(model, NBRDF_BASE_CONDUCTOR, 1, &c, &d, NBRDF_RANGE_REFUSE,
                                    bottom, NULL, err),
           err);
  CHECK_OK(nbrdf_model_layer(model, 1, top, bottom, &t[4], &t[5], latent, err), err);
  CHECK_OK(nbrdf_model_proxy_params(model, 1, latent, sigma, w, err), err);
  free(top);
}

/* Texel (x, y) of `level`, all channels, logical order. */
static float *read_texel(const char *file, int level, int x, int y, texture_latent_info *info) {
  nbrdf_error e, *err = &e;
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, file, err), err);
  if (!r) return NULL;
  *info = *texture_latent_reader_info(r);
  float *t = malloc(sizeof(float) * info->channels);
  CHECK_OK(texture_latent_reader_read(r, level, x, y, 1, 1, t, err), err);
  texture_latent_reader_close(r);
  info->model_name = info->model_checksum = info->sources = info->settings = "";
  return t;
}

static void check_texel(const float *texel, const texture_latent_layout *L, int c, const float t[6],
                        double tol) {
  int D = L->latent_dim;
  float *lat = malloc(sizeof(float) * D), sigma, w;
  direct(t, lat, &sigma, &w);
  for (int k = 0; k < D; k++)
    CHECK_NEAR(texel[texture_latent_index_latent(L, c, k)], lat[k], tol);
  CHECK_NEAR(texel[texture_latent_index_sigma(L, c)], sigma, tol * (1 + fabs(sigma)));
  CHECK_NEAR(texel[texture_latent_index_w(L, c)], w, tol);
  free(lat);
}

static void test_constants(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = constants();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.storage = NBRDF_BAKE_FLOAT;
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("const.exr"), &rep, err), err);
  CHECK(rep.width == 1 && rep.height == 1 && rep.colour_channels == 1 && rep.evaluated == 1);
  /* An output size for constants (issue 21): one tuple, any size; bad sizes refused. */
  nbrdf_bake_inputs sized = in;
  sized.width = 300, sized.height = 7;
  CHECK_OK(nbrdf_bake(model, &sized, &o, path("const_sized.exr"), &rep, err), err);
  CHECK(rep.width == 300 && rep.height == 7 && rep.evaluated == 1);
  sized.width = 0;
  CHECK_FAILS(nbrdf_bake(model, &sized, &o, path("bad_size.exr"), &rep, err), NBRDF_ERR_ARGUMENT,
              err, "1..65536");
  sized.width = NBRDF_BAKE_SIZE_MAX + 1;
  CHECK_FAILS(nbrdf_bake(model, &sized, &o, path("bad_size.exr"), &rep, err), NBRDF_ERR_ARGUMENT,
              err, "65537x7");
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, path("const.exr"), err), err);
  if (!r) return;
  const texture_latent_info *info = texture_latent_reader_info(r);
  CHECK(info->layout.colour == NBRDF_COLOUR_MONO && info->layout.proxy == 1);
  CHECK(info->layout.latent_dim == nbrdf_model_latent_dim(model));
  CHECK(info->storage == NBRDF_LATENT_FLOAT && info->levels == 1);
  CHECK(!strcmp(info->model_checksum, nbrdf_model_checksum(model)));
  CHECK(strstr(info->sources, "eta=") && strstr(info->settings, "roughness=alpha"));
  CHECK_OK(texture_latent_check_model(info, "const.exr", nbrdf_model_name(model),
                                      nbrdf_model_checksum(model), err),
           err);
  float *texel = malloc(sizeof(float) * info->channels);
  CHECK_OK(texture_latent_reader_read(r, 0, 0, 0, 1, 1, texel, err), err);
  float t[6];
  for (int id = 0; id < 6; id++)
    t[id] = in.param[id].value[0];
  check_texel(texel, &info->layout, 0, t, 1e-5);
  free(texel);
  texture_latent_reader_close(r);
}

/* 16 x 16 maps: alpha1 a float gradient of 4 distinct values, r0 an RGB map;
 * the rest constants. */
static void write_maps(void) {
  nbrdf_error e, *err = &e;
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  float a[256], r0[256 * 3];
  for (int y = 0; y < 16; y++)
    for (int x = 0; x < 16; x++) {
      a[y * 16 + x] = lo[0] + (hi[0] - lo[0]) * (float)(x / 4) / 4.0f;
      for (int c = 0; c < 3; c++)
        r0[(y * 16 + x) * 3 + c] = (float)((x + y * 3 + c * 5) % 8) / 8.0f;
    }
  CHECK_OK(texture_image_write(path("alpha1.exr"), 16, 16, 1, a, NBRDF_PIXEL_FLOAT, err), err);
  CHECK_OK(texture_image_write(path("r0.exr"), 16, 16, 3, r0, NBRDF_PIXEL_FLOAT, err), err);
  CHECK_OK(texture_image_write(path("small.exr"), 8, 8, 1, a, NBRDF_PIXEL_FLOAT, err), err);
  a[5 * 16 + 3] = NAN;
  CHECK_OK(texture_image_write(path("nan.exr"), 16, 16, 1, a, NBRDF_PIXEL_FLOAT, err), err);
}

static void test_maps(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = constants();
  in.param[NBRDF_BAKE_ALPHA1].path = path("alpha1.exr");
  in.param[NBRDF_BAKE_R0].path = path("r0.exr");
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.storage = NBRDF_BAKE_FLOAT;
  o.tile_size = 8;
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("maps.exr"), &rep, err), err);
  CHECK(rep.width == 16 && rep.height == 16 && rep.colour_channels == 3);
  CHECK_MSG(rep.evaluated < rep.brdfs, "distinct %zu of %zu", rep.evaluated, rep.brdfs);
  texture_latent_info info;
  int x = 9, y = 6;
  float *texel = read_texel(path("maps.exr"), 0, x, y, &info);
  if (!texel) return;
  CHECK(info.layout.colour == NBRDF_COLOUR_RGB && info.levels == 5 && info.width == 16);
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  for (int c = 0; c < 3; c++) {
    float t[6];
    for (int id = 0; id < 6; id++)
      t[id] = in.param[id].value[0];
    t[NBRDF_BAKE_ALPHA1] = lo[0] + (hi[0] - lo[0]) * (float)(x / 4) / 4.0f;
    t[NBRDF_BAKE_R0] = (float)((x + y * 3 + c * 5) % 8) / 8.0f;
    check_texel(texel, &info.layout, c, t, 1e-5);
  }
  free(texel);

  /* Level 1 texel (2, 1): mean of the 2 x 2 latents; its proxy is predicted from that mean. */
  float *mip = read_texel(path("maps.exr"), 1, 2, 1, &info);
  float *q[4];
  for (int k = 0; k < 4; k++)
    q[k] = read_texel(path("maps.exr"), 0, 4 + (k & 1), 2 + (k >> 1), &info);
  int D = info.layout.latent_dim;
  float *mean = malloc(sizeof(float) * D), sigma, w;
  for (int c = 0; c < 3 && mip; c++) {
    for (int k = 0; k < D; k++) {
      int i = texture_latent_index_latent(&info.layout, c, k);
      mean[k] = (float)(((double)q[0][i] + q[1][i] + q[2][i] + q[3][i]) / 4.0);
      CHECK_NEAR(mip[i], mean[k], 1e-5);
    }
    CHECK_OK(nbrdf_model_proxy_params(model, 1, mean, &sigma, &w, err), err);
    CHECK_NEAR(mip[texture_latent_index_sigma(&info.layout, c)], sigma, 1e-4 * (1 + sigma));
    CHECK_NEAR(mip[texture_latent_index_w(&info.layout, c)], w, 1e-4);
  }
  free(mean);
  free(mip);
  for (int k = 0; k < 4; k++)
    free(q[k]);
}

static void test_bad_inputs(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = constants();
  in.param[NBRDF_BAKE_ALPHA1].path = path("alpha1.exr");
  in.param[NBRDF_BAKE_ETA].path = path("small.exr");
  CHECK_FAILS(nbrdf_bake(model, &in, NULL, path("bad.exr"), NULL, err), NBRDF_ERR_MISMATCH, err,
              "small.exr");
  CHECK_MSG(strstr(e.message, "small.exr") != NULL, "message: %s", e.message);
  CHECK(!exists(path("bad.exr")));

  in = constants();
  in.param[NBRDF_BAKE_SIGMA_T].path = path("nan.exr");
  CHECK_FAILS(nbrdf_bake(model, &in, NULL, path("bad.exr"), NULL, err), NBRDF_ERR_ARGUMENT, err,
              "(3, 5)");
  CHECK_MSG(strstr(e.message, "nan.exr") && strstr(e.message, "(3, 5)"), "message: %s", e.message);
  CHECK(!exists(path("bad.exr")));

  /* The output may not be one of the inputs; the input is untouched. */
  in = constants();
  in.param[NBRDF_BAKE_ALPHA1].path = path("alpha1.exr");
  struct stat before, after;
  stat(path("alpha1.exr"), &before);
  CHECK(nbrdf_bake(model, &in, NULL, path("alpha1.exr"), NULL, err) != NBRDF_OK);
  stat(path("alpha1.exr"), &after);
  CHECK(before.st_size == after.st_size && before.st_mtime == after.st_mtime);

  /* Outside the trained range: refused naming the texel, or clamped with a warning. */
  in = constants();
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA2], 50.0f);
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.range = NBRDF_RANGE_REFUSE;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("bad.exr"), NULL, err), NBRDF_ERR_ARGUMENT, err,
              "trained range");
  CHECK_MSG(strstr(e.message, "alpha2") && strstr(e.message, "trained range"), "%s", e.message);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALBEDO], 1.5f);
  o.range = NBRDF_RANGE_CLAMP;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("bad.exr"), NULL, err), NBRDF_ERR_ARGUMENT, err,
              "above 1");
  CHECK_MSG(strstr(e.message, "albedo") != NULL, "%s", e.message);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALBEDO], 0.5f);
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("clamped.exr"), &rep, err), err);
  CHECK(rep.clamped == 1);
  CHECK(!exists(path("bad.exr")) && no_temporaries());
}

static int cancel_at_second(void *user, const char *stage, double done, double total) {
  (void)stage, (void)total;
  (*(int *)user)++;
  return done > 0;
}

static void test_cancel(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = constants();
  in.param[NBRDF_BAKE_ALPHA1].path = path("alpha1.exr");
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  int calls = 0;
  o.progress = cancel_at_second;
  o.user = &calls;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("cancel.exr"), NULL, err), NBRDF_ERR_CANCELLED, err,
              "cancelled");
  CHECK(calls >= 2 && !exists(path("cancel.exr")) && no_temporaries());
  volatile sig_atomic_t flag = 1;
  o = (nbrdf_bake_options)NBRDF_BAKE_OPTIONS_DEFAULT;
  o.cancel = &flag;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("cancel.exr"), NULL, err), NBRDF_ERR_CANCELLED, err,
              "cancelled");
  CHECK(!exists(path("cancel.exr")) && no_temporaries());
}

/* Perceptual roughness r bakes as alpha = r^2. */
static void test_perceptual(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = constants();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.storage = NBRDF_BAKE_FLOAT;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("alpha.exr"), NULL, err), err);
  for (int id = 0; id <= NBRDF_BAKE_ALPHA2; id += 2)
    nbrdf_bake_param_constant(&in.param[id], sqrtf(in.param[id].value[0]));
  o.roughness = NBRDF_ROUGHNESS_PERCEPTUAL;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("perceptual.exr"), NULL, err), err);
  texture_latent_info ia, ib;
  float *a = read_texel(path("alpha.exr"), 0, 0, 0, &ia);
  float *b = read_texel(path("perceptual.exr"), 0, 0, 0, &ib);
  for (int i = 0; a && b && i < ia.channels; i++)
    CHECK_NEAR(a[i], b[i], 1e-5 * (1 + fabs(a[i])));
  free(a);
  free(b);
}

/* 8-bit maps: albedo and r0 are sRGB colour data and linearised, alpha is
 * non-colour data and used as stored. */
static void test_colour_maps(void) {
  nbrdf_error e, *err = &e;
  float lo[2], hi[2];
  grid(NBRDF_BASE_CONDUCTOR, lo, hi);
  float v8 = 140.0f / 255.0f, img[4 * 4];
  for (int i = 0; i < 16; i++)
    img[i] = v8;
  CHECK_OK(texture_image_write(path("v8.png"), 4, 4, 1, img, NBRDF_PIXEL_U8, err), err);
  nbrdf_bake_inputs in = constants();
  in.param[NBRDF_BAKE_ALPHA2].path = path("v8.png");
  in.param[NBRDF_BAKE_ALBEDO].path = path("v8.png");
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.storage = NBRDF_BAKE_FLOAT;
  o.range = NBRDF_RANGE_REFUSE;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("colour.exr"), NULL, err), err);
  texture_latent_info info;
  float *texel = read_texel(path("colour.exr"), 0, 2, 1, &info);
  if (!texel) return;
  float t[6];
  for (int id = 0; id < 6; id++)
    t[id] = in.param[id].value[0];
  t[NBRDF_BAKE_ALPHA2] = v8;
  t[NBRDF_BAKE_ALBEDO] = (float)pow((v8 + 0.055) / 1.055, 2.4);
  CHECK(v8 >= lo[0] && v8 <= hi[0]);
  check_texel(texel, &info.layout, 0, t, 1e-4);
  free(texel);

  /* A folder that does not exist, a file that does not exist. */
  in = constants();
  CHECK_FAILS(nbrdf_bake(model, &in, NULL, path("no/such/dir.exr"), NULL, err), NBRDF_ERR_IO, err,
              "no/such");
  in.param[NBRDF_BAKE_ETA].path = path("missing.exr");
  CHECK(nbrdf_bake(model, &in, NULL, path("bad.exr"), NULL, err) != NBRDF_OK);
  CHECK_MSG(strstr(e.message, "missing.exr") != NULL, "%s", e.message);
  CHECK(!exists(path("bad.exr")));
}

/* DESIGN.md's extremes: alpha at the grid's edge, eta -> 1, R0 and A in
 * {0, 1}, sigma_t 0 and large (clamped, with a warning). */
static void warn_count(void *user, const char *message) {
  (void)message;
  (*(int *)user)++;
}

static void collect(void *user, const char *message) {
  char *buf = user;
  size_t len = strlen(buf);
  snprintf(buf + len, 2048 - len, "%s\n", message);
}

/* The energy audit: every evaluated latent audited, the header's
 * nbrdf:maxAlbedo equal to the largest decoded albedo of the texels read
 * back, a capped audit says so, no audit leaves the attribute unset, and the
 * warning names a texel and its parameters. */
static void test_energy_audit(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = constants();
  char a1[640], r0[640]; /* path() reuses its buffers */
  snprintf(a1, sizeof a1, "%s", path("alpha1.exr"));
  snprintf(r0, sizeof r0, "%s", path("r0.exr"));
  in.param[NBRDF_BAKE_ALPHA1].path = a1;
  in.param[NBRDF_BAKE_R0].path = r0;
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.storage = NBRDF_BAKE_FLOAT;
  o.mip_levels = 1;
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("audit.exr"), &rep, err), err);
  CHECK(rep.audited == rep.evaluated && rep.audited > 1 && rep.max_albedo > 0.0);
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, path("audit.exr"), err), err);
  if (!r) return;
  const texture_latent_info *info = texture_latent_reader_info(r);
  CHECK_NEAR(info->max_albedo, (float)rep.max_albedo, 0.0);
  int C = texture_latent_colours(&info->layout), D = info->layout.latent_dim;
  size_t n = (size_t)info->width * info->height;
  float *tex = malloc(n * info->channels * sizeof *tex);
  float *lat = malloc(n * C * D * sizeof *lat), *sig = malloc(n * C * sizeof *sig);
  double *mx = malloc(n * C * sizeof *mx);
  CHECK_OK(texture_latent_reader_read(r, 0, 0, 0, info->width, info->height, tex, err), err);
  for (size_t i = 0; i < n; i++)
    for (int c = 0; c < C; c++) {
      for (int k = 0; k < D; k++)
        lat[(i * C + c) * D + k] =
            tex[i * info->channels + texture_latent_index_latent(&info->layout, c, k)];
      sig[i * C + c] = tex[i * info->channels + texture_latent_index_sigma(&info->layout, c)];
    }
  CHECK_OK(bake_albedo_precise(model, NULL, n * C, lat, sig, mx, NULL, err), err);
  double worst = 0.0;
  for (size_t k = 0; k < n * C; k++)
    worst = fmax(worst, mx[k]);
  /* The audit measures some tuples and clears the others by a bound from a measured one
   * in the same or the next cell (bake_audit.h): its worst is one of these latents'
   * values, so at most the largest (1e-4 relative: other GEMM shapes, a few float ulps
   * through the decoder and the sum; OpenBLAS's result for a row can depend on the rows
   * beside it), and at least the largest less the bound's widest reach (every slope over
   * two cells, the quadrature's noise, and the gap of a tuple measured at the screen's
   * three angles only). */
  double reach = BAKE_AUDIT_THETA_GAP, slope[NBRDF_BAKE_PARAM_COUNT];
  if (model_audit_slopes(model)) {
    reach += BAKE_AUDIT_NOISE;
    bake_audit_slope_max(model_audit_slopes(model), slope);
    for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
      reach += 2.0 * slope[id] / BAKE_AUDIT_GRID;
  } else { /* a bundle without slopes (this one): every tuple measured */
    CHECK(rep.audit_measured == rep.audited);
  }
  CHECK(rep.max_albedo <= worst * (1.0 + 1e-4));
  CHECK_MSG(rep.max_albedo >= worst * (1.0 - 1e-4) - reach, "%g vs %g", rep.max_albedo, worst);
  free(tex), free(lat), free(sig), free(mx);
  texture_latent_reader_close(r);

  char msgs[2048] = "";
  o.warning = collect, o.user = msgs, o.energy_audit = 2;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("audit2.exr"), &rep, err), err);
  CHECK(rep.audited == 2 && strstr(msgs, "not audited"));
  o.energy_audit = 0;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("audit0.exr"), &rep, err), err);
  CHECK(rep.audited == 0 && isnan(rep.max_albedo));
  CHECK_OK(texture_latent_reader_open(&r, path("audit0.exr"), err), err);
  if (r) CHECK(isnan(texture_latent_reader_info(r)->max_albedo));
  texture_latent_reader_close(r);

  bake_audit a;
  bake_audit_init(&a, 10);
  a.audited = 4, a.over = 1, a.worst = 1.2, a.worst_theta = 4;
  bake_tuple t = {{0.01f, 1.1f, 0.3f, 0.9f, 0.8f, 0.0f}};
  bake_audit_found(&a, &t, 3, 4, 1);
  char m[512];
  bake_audit_message(&a, 1, m, sizeof m);
  CHECK_MSG(strstr(m, "1 of 4") && strstr(m, "1.200 at theta_i = 85") &&
                strstr(m, "texel (3, 4) channel G") && strstr(m, "alpha1=0.01 eta=1.1"),
            "%s", m);
  a.worst = 1.005;
  bake_audit_message(&a, 0, m, sizeof m);
  CHECK(m[0] == '\0');
  bake_audit_free(&a);
}

static void test_extremes(void) {
  nbrdf_error e, *err = &e;
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  nbrdf_bake_inputs in = constants();
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA1], lo[0]);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ETA], 1.0f);
  nbrdf_bake_param *r0 = &in.param[NBRDF_BAKE_R0], *a = &in.param[NBRDF_BAKE_ALBEDO];
  r0->channels = a->channels = 3;
  r0->value[0] = 0.0f, r0->value[1] = 1.0f, r0->value[2] = 0.5f;
  a->value[0] = 1.0f, a->value[1] = 0.0f, a->value[2] = 1.0f;
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_SIGMA_T], 100.0f);
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  int warnings = 0;
  o.warning = warn_count;
  o.user = &warnings;
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("extremes.exr"), &rep, err), err);
  int eta_inside = 1.0f >= lo[1];
  /* sigma_t clamped on 3 channels, eta on 3 unless the grid reaches 1 */
  CHECK_MSG(rep.clamped == (size_t)(eta_inside ? 3 : 6), "clamped %zu", rep.clamped);
  CHECK(warnings == (eta_inside ? 1 : 2));
  texture_latent_info info;
  float *t = read_texel(path("extremes.exr"), 0, 0, 0, &info);
  for (int i = 0; t && i < info.channels; i++)
    CHECK(isfinite(t[i]));
  CHECK(t && info.layout.colour == NBRDF_COLOUR_RGB);
  free(t);
}

static unsigned char *slurp(const char *p, long *n) {
  FILE *f = fopen(p, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  *n = ftell(f);
  rewind(f);
  unsigned char *buf = malloc((size_t)*n);
  if (fread(buf, 1, (size_t)*n, f) != (size_t)*n) *n = -1;
  fclose(f);
  return buf;
}

static void test_deterministic(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = constants();
  in.param[NBRDF_BAKE_ALPHA1].path = path("alpha1.exr");
  in.param[NBRDF_BAKE_R0].path = path("r0.exr");
  CHECK_OK(nbrdf_bake(model, &in, NULL, path("d1.exr"), NULL, err), err);
  CHECK_OK(nbrdf_bake(model, &in, NULL, path("d2.exr"), NULL, err), err);
  long n1 = 0, n2 = 0;
  unsigned char *a = slurp(path("d1.exr"), &n1), *b = slurp(path("d2.exr"), &n2);
  CHECK(a && b && n1 > 0 && n1 == n2 && !memcmp(a, b, (size_t)n1));
  free(a);
  free(b);
}

/* The largest difference between two textures' level-0 values, relative to
 * each channel's largest magnitude (HUGE_VAL if they cannot be compared). */
static double texel_difference(const char *a, const char *b) {
  double worst = HUGE_VAL;
  texture_latent_info ia, ib;
  nbrdf_error e, *err = &e;
  texture_latent_reader *ra = NULL, *rb = NULL;
  CHECK_OK(texture_latent_reader_open(&ra, a, err), err);
  CHECK_OK(texture_latent_reader_open(&rb, b, err), err);
  if (!ra || !rb) goto done;
  ia = *texture_latent_reader_info(ra), ib = *texture_latent_reader_info(rb);
  if (ia.width != ib.width || ia.height != ib.height || ia.channels != ib.channels) goto done;
  size_t n = (size_t)ia.width * ia.height, C = (size_t)ia.channels;
  float *ta = malloc(sizeof(float) * n * C), *tb = malloc(sizeof(float) * n * C);
  CHECK_OK(texture_latent_reader_read(ra, 0, 0, 0, ia.width, ia.height, ta, err), err);
  CHECK_OK(texture_latent_reader_read(rb, 0, 0, 0, ib.width, ib.height, tb, err), err);
  worst = 0;
  for (size_t c = 0; c < C; c++) {
    double scale = 0;
    for (size_t i = 0; i < n; i++)
      scale = fmax(scale, fabs(ta[i * C + c]));
    for (size_t i = 0; i < n; i++) {
      double d = fabs((double)ta[i * C + c] - tb[i * C + c]) / fmax(scale, 1e-30);
      if (!(d <= worst)) worst = isnan(d) ? HUGE_VAL : d;
    }
  }
  free(ta);
  free(tb);
done:
  texture_latent_reader_close(ra);
  texture_latent_reader_close(rb);
  return worst;
}

/* The cross-band tuple cache changes which band evaluates a tuple, never
 * the texels: bakes with the cache, with one too small to hold a band's
 * tuples, and without it agree within float rounding. 4096 x 48 texels are
 * three bands of 16 rows; alpha1 takes 5 values in an order that changes
 * from row to row, sigma_t adds a value in the last band only. */
static void test_tuple_cache(void) {
  nbrdf_error e, *err = &e;
  const int W = 4096, H = 48;
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  float *a = malloc(sizeof(float) * W * H), *s = malloc(sizeof(float) * W * H);
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      a[y * W + x] = lo[0] + (hi[0] - lo[0]) * (float)((x * 7 + y) % 5) / 5.0f;
      s[y * W + x] = y >= 32 && x % 2 ? 2.0f : 1.0f;
    }
  CHECK_OK(texture_image_write(path("wide_a.exr"), W, H, 1, a, NBRDF_PIXEL_FLOAT, err), err);
  CHECK_OK(texture_image_write(path("wide_s.exr"), W, H, 1, s, NBRDF_PIXEL_FLOAT, err), err);
  free(a);
  free(s);
  char pa[640], ps[640];
  snprintf(pa, sizeof pa, "%s", path("wide_a.exr"));
  snprintf(ps, sizeof ps, "%s", path("wide_s.exr"));
  nbrdf_bake_inputs in = constants();
  in.param[NBRDF_BAKE_ALPHA1].path = pa;
  in.param[NBRDF_BAKE_SIGMA_T].path = ps;
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.storage = NBRDF_BAKE_FLOAT;
  o.mip_levels = 1; /* the cache is about level 0; mips would only add time */
  static const size_t caches[3] = {NBRDF_BAKE_TUPLE_CACHE_DEFAULT, 3, 0};
  static const size_t evaluated[3] = {10, 20, 20}, reused[3] = {10, 0, 0};
  char files[3][640]; /* path() recycles its buffers */
  snprintf(files[0], sizeof files[0], "%s", path("cache.exr"));
  snprintf(files[1], sizeof files[1], "%s", path("cache3.exr"));
  snprintf(files[2], sizeof files[2], "%s", path("nocache.exr"));
  for (int k = 0; k < 3; k++) {
    nbrdf_bake_report rep;
    o.tuple_cache = caches[k];
    CHECK_OK(nbrdf_bake(model, &in, &o, files[k], &rep, err), err);
    /* bands: 5, 5, 10 distinct tuples */
    CHECK_MSG(rep.evaluated == evaluated[k] && rep.reused == reused[k],
              "cache %zu: evaluated %zu, reused %zu", caches[k], rep.evaluated, rep.reused);
  }
  /* Bytes are not compared: a BLAS may round a row differently depending on
   * how many rows share the call (OpenBLAS's Haswell and Zen kernels do), and
   * the cache changes how many tuples a band evaluates together. Float
   * rounding through the networks measured 6e-6 of a channel's scale. */
  for (int k = 1; k < 3; k++) {
    double d = texel_difference(files[0], files[k]);
    CHECK_MSG(d <= 1e-4, "%s differs from %s by %.3g of a channel's scale", files[k], files[0], d);
  }
  /* ... and the comparison sees a real change: another sigma_t everywhere. */
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_SIGMA_T], 3.0f);
  CHECK_OK(nbrdf_bake(model, &in, &o, path("other.exr"), NULL, err), err);
  CHECK(texel_difference(files[0], path("other.exr")) > 1e-2);
}

/* The documented rule, written out independently: 2^bits levels over the
 * trained range, alpha evenly in sqrt(alpha), sigma_t in log1p, the rest
 * linearly. */
static float quantised(int id, float v, int bits) {
  float lo[2], hi[2], l, h;
  grid(id == NBRDF_BAKE_ALPHA1 || id == NBRDF_BAKE_ETA ? NBRDF_BASE_DIELECTRIC
                                                       : NBRDF_BASE_CONDUCTOR,
       lo, hi);
  int k = id == NBRDF_BAKE_ETA || id == NBRDF_BAKE_R0;
  l = lo[k], h = hi[k];
  if (id == NBRDF_BAKE_ALBEDO) l = 0, h = 1;
  if (id == NBRDF_BAKE_SIGMA_T) l = 0, h = NBRDF_BAKE_SIGMA_T_MAX;
  int alpha = id == NBRDF_BAKE_ALPHA1 || id == NBRDF_BAKE_ALPHA2, sig = id == NBRDF_BAKE_SIGMA_T;
  double wl = alpha ? sqrt(l) : sig ? log1p(l) : l, wh = alpha ? sqrt(h) : sig ? log1p(h) : h;
  double wv = alpha ? sqrt(v) : sig ? log1p(v) : v, steps = (1 << bits) - 1;
  double q = round((wv - wl) / (wh - wl) * steps), u = wl + (wh - wl) * q / steps;
  return (float)(alpha ? u * u : sig ? expm1(u) : u);
}

/* Quantisation: every parameter rounded to 2^3 levels; the texel holds the
 * latent of the rounded tuple; bits out of range are refused. */
static void test_quantise(void) {
  nbrdf_error e, *err = &e;
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  float a[64];
  for (int x = 0; x < 64; x++)
    a[x] = lo[0] + (hi[0] - lo[0]) * (float)x / 63.0f;
  char pa[640];
  snprintf(pa, sizeof pa, "%s", path("quant_a.exr"));
  CHECK_OK(texture_image_write(pa, 64, 1, 1, a, NBRDF_PIXEL_FLOAT, err), err);
  nbrdf_bake_inputs in = constants();
  in.param[NBRDF_BAKE_ALPHA1].path = pa;
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.storage = NBRDF_BAKE_FLOAT;
  o.mip_levels = 1;
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("unquantised.exr"), &rep, err), err);
  CHECK(rep.evaluated == 64);
  o.quantise_bits = 3;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("quantised.exr"), &rep, err), err);
  CHECK_MSG(rep.evaluated == 8, "evaluated %zu with 3 bits", rep.evaluated);
  for (int x = 5; x < 64; x += 29) {
    float t[6];
    for (int id = 0; id < 6; id++)
      t[id] = quantised(id, id == NBRDF_BAKE_ALPHA1 ? a[x] : in.param[id].value[0], 3);
    texture_latent_info info;
    float *texel = read_texel(path("quantised.exr"), 0, x, 0, &info);
    if (texel) check_texel(texel, &info.layout, 0, t, 1e-4);
    CHECK(texel != NULL);
    free(texel);
  }
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, path("quantised.exr"), err), err);
  CHECK(r && strstr(texture_latent_reader_info(r)->settings, "quantise=3") != NULL);
  texture_latent_reader_close(r);
  o.quantise_bits = 1;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("bad.exr"), NULL, err), NBRDF_ERR_ARGUMENT, err,
              "quantise_bits");
  CHECK(!exists(path("bad.exr")));
}

/* Maps of different sizes: refused by default (the message names both),
 * enlarged bilinearly to the largest with NBRDF_RESAMPLE_BILINEAR: a 2 x 1
 * eta map [1.2, 1.8] over 16 x 16 gives eta(x) = 1.2 + 0.6 * clamp((x + 0.5)
 * / 8 - 0.5, 0, 1), constant down the columns. */
static void test_resample(void) {
  nbrdf_error e, *err = &e;
  float eta[2] = {1.2f, 1.8f};
  char pe[640], pa[640];
  snprintf(pe, sizeof pe, "%s", path("eta2x1.exr"));
  snprintf(pa, sizeof pa, "%s", path("alpha1.exr"));
  CHECK_OK(texture_image_write(pe, 2, 1, 1, eta, NBRDF_PIXEL_FLOAT, err), err);
  nbrdf_bake_inputs in = constants();
  in.param[NBRDF_BAKE_ALPHA1].path = pa;
  in.param[NBRDF_BAKE_ETA].path = pe;
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.storage = NBRDF_BAKE_FLOAT;
  o.mip_levels = 1;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("bad.exr"), NULL, err), NBRDF_ERR_MISMATCH, err,
              "eta2x1.exr");
  CHECK_MSG(strstr(e.message, "alpha1.exr") && strstr(e.message, "resampled") &&
                strstr(e.message, "bilinear"),
            "%s", e.message);
  CHECK(!exists(path("bad.exr")));
  in.resample = NBRDF_RESAMPLE_BILINEAR;
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(model, &in, &o, path("resampled.exr"), &rep, err), err);
  CHECK(rep.width == 16 && rep.height == 16);
  float lo[2], hi[2];
  grid(NBRDF_BASE_DIELECTRIC, lo, hi);
  static const int xs[3] = {0, 6, 13};
  for (int k = 0; k < 3; k++) {
    int x = xs[k], y = 11;
    double u = (x + 0.5) / 8.0 - 0.5;
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    float t[6];
    for (int id = 0; id < 6; id++)
      t[id] = in.param[id].value[0];
    t[NBRDF_BAKE_ALPHA1] = lo[0] + (hi[0] - lo[0]) * (float)(x / 4) / 4.0f;
    t[NBRDF_BAKE_ETA] = (float)(1.2 + 0.6 * u);
    texture_latent_info info;
    float *texel = read_texel(path("resampled.exr"), 0, x, y, &info);
    if (texel) check_texel(texel, &info.layout, 0, t, 1e-4);
    free(texel);
  }
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, path("resampled.exr"), err), err);
  CHECK(r && strstr(texture_latent_reader_info(r)->sources, "bilinear 2x1 -> 16x16") != NULL);
  texture_latent_reader_close(r);

  /* Bands of 3 rows (sharing source rows across bands) read the same values
   * as one band of 37: r0.exr (16 x 16 RGB) enlarged to 23 x 37. */
  texture_param_map_options mo = NBRDF_PARAM_MAP_OPTIONS_DEFAULT;
  texture_param_source *one = NULL, *three = NULL;
  CHECK_OK(texture_param_source_map("r0", path("r0.exr"), &mo, &one, err), err);
  CHECK_OK(texture_param_source_map("r0", path("r0.exr"), &mo, &three, err), err);
  if (!one || !three) return;
  CHECK_FAILS(texture_param_source_resample(one, 0, 37, err), NBRDF_ERR_ARGUMENT, err, "0x37");
  CHECK_OK(texture_param_source_resample(one, 23, 37, err), err);
  CHECK_OK(texture_param_source_resample(three, 23, 37, err), err);
  texture_param_band all, part;
  CHECK_OK(texture_param_source_read_band(one, 0, 37, &all, err), err);
  int mismatches = 0;
  for (int y0 = 0; y0 < 37; y0 += 3) {
    int rows = 37 - y0 < 3 ? 37 - y0 : 3;
    CHECK_OK(texture_param_source_read_band(three, y0, rows, &part, err), err);
    for (int j = 0; j < rows; j++)
      for (int x = 0; x < 23; x++)
        for (int c = 0; c < 3; c++)
          mismatches +=
              texture_param_band_at(&part, x, j, c) != texture_param_band_at(&all, x, y0 + j, c);
  }
  CHECK_MSG(mismatches == 0, "%d values differ between band sizes", mismatches);
  /* Corners are the source's corners (edges clamped). */
  CHECK(texture_param_band_at(&all, 0, 0, 1) == (float)((0 + 0 + 5) % 8) / 8.0f);
  texture_param_source_free(one);
  texture_param_source_free(three);
}

int main(void) {
  nbrdf_error e, *err = &e;
  snprintf(tmp, sizeof tmp, "%s", testing_tmpdir());
  CHECK_OK(model_bundle_init_random(path("bundle"), "bake-test", 7, "small", err), err);
  CHECK_OK(nbrdf_model_load(path("bundle"), &model, err), err);
  if (!model) return testing_finish();
  write_maps();
  RUN(test_constants);
  RUN(test_maps);
  RUN(test_energy_audit);
  RUN(test_bad_inputs);
  RUN(test_cancel);
  RUN(test_perceptual);
  RUN(test_colour_maps);
  RUN(test_extremes);
  RUN(test_deterministic);
  RUN(test_tuple_cache);
  RUN(test_quantise);
  RUN(test_resample);
  nbrdf_model_destroy(model);
  return testing_finish();
}
