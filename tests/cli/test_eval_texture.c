/* `nbrdf eval --texture` decodes a texture as a renderer does (issue 17):
 * on a version-2 bake carrying its own decoder (the default decoder with
 * perturbed weights), eval's f at texel centres of levels 0 and 1 equals the
 * library's decode of those texels with nbrdf_model_for_texture's model, and
 * between centres the bilinear fetch of texture/latent_fetch.c; it differs
 * from the bundle's decode; the GPU packer, given that model, packs exactly
 * the embedded decoder's weights. The committed version-1 texture is decoded
 * with the decoder of the bundle it was baked with (models/v1, the default
 * until 2026-11-26). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/bundle.h"
#include "nbrdf/gpu_pack.h"
#include "testing.h"
#include "texture/latent_exr.h"
#include "texture/latent_fetch.h"

#define N_DIRS 4
static const double DIRS[N_DIRS][4] = {
    {30, 0, 30, 180}, {0, 0, 0, 0}, {60, 10, 20, 250}, {45, 90, 70, -30}};

static nbrdf_model *bundle;
static const char *eval_bundle = "models/default"; /* what run_eval passes to --bundle */
static char tmp[512];

static const char *path(const char *name) {
  static char buf[4][640];
  static int k;
  k = (k + 1) % 4;
  snprintf(buf[k], sizeof buf[k], "%s/%s", tmp, name);
  return buf[k];
}

static const char *cli_bin(void) {
  const char *b = getenv("NBRDF");
  return b ? b : "nbrdf";
}

typedef struct query {
  double u, v;
  int dir;
} query;

static void direction(const double *d, float *wi, float *wo) {
  for (int s = 0; s < 2; s++) {
    double th = d[2 * s] * (M_PI / 180.0), ph = d[2 * s + 1] * (M_PI / 180.0);
    float *w = s ? wo : wi;
    w[0] = (float)(sin(th) * cos(ph)), w[1] = (float)(sin(th) * sin(ph)), w[2] = (float)cos(th);
  }
}

/* Runs eval --texture on the queries; f[k * 3 + c]. Returns the rows read. */
static int run_eval(const char *tex, int level, const query *q, int n, double *f) {
  FILE *c = fopen(path("q.csv"), "w");
  if (!c) return 0;
  fprintf(c, "id,u,v,theta_i,phi_i,theta_o,phi_o\n");
  for (int k = 0; k < n; k++) {
    const double *d = DIRS[q[k].dir];
    fprintf(c, "q%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", k, q[k].u, q[k].v, d[0], d[1], d[2],
            d[3]);
  }
  fclose(c);
  char cmd[4096];
  snprintf(cmd, sizeof cmd,
           "'%s' eval --texture '%s' --level %d --bundle '%s/%s' --in '%s' >'%s'",
           cli_bin(), tex, level, testing_source_dir(), eval_bundle, path("q.csv"), path("out.csv"));
  CHECK_MSG(system(cmd) == 0, "eval failed: %s", cmd);
  FILE *o = fopen(path("out.csv"), "r");
  char line[1024];
  int row = -1;
  while (o && fgets(line, sizeof line, o)) {
    if (row < 0) {
      CHECK(!strcmp(line, "id,u,v,theta_i,phi_i,theta_o,phi_o,f_r,f_g,f_b\n"));
    } else if (row < n) {
      char *p = line;
      for (int comma = 0; comma < 7 && p; comma++)
        p = strchr(p, ','), p = p ? p + 1 : NULL;
      for (int ch = 0; ch < 3 && p; ch++) {
        f[row * 3 + ch] = strtod(p, &p);
        if (*p == ',') p++;
      }
    }
    row++;
  }
  if (o) fclose(o);
  return row;
}

/* The library's decode of the bilinear fetch at each query, with `m`. */
static void reference(const nbrdf_model *m, const texture_latent_image *img, int level,
                      const query *q, int n, float *f) {
  nbrdf_error err = {0};
  float texel[3 * 34];
  CHECK(img->channels == 3 * 34);
  for (int k = 0; k < n; k++) {
    float lat[3 * 32], wi[3], wo[3];
    texture_latent_fetch_level(img, level, (float)q[k].u, (float)q[k].v, texel);
    for (int c = 0; c < 3; c++)
      memcpy(lat + 32 * c, texel + texture_latent_index_latent(&img->layout, c, 0),
             32 * sizeof(float));
    direction(DIRS[q[k].dir], wi, wo);
    CHECK_OK(nbrdf_model_decode(m, 1, 3, lat, wi, wo, f + 3 * k, &err), &err);
  }
}

static int close_to(double a, double b) { return fabs(a - b) <= 1e-5 * fabs(b) + 1e-7; }

static void test_own_decoder(void) {
  nbrdf_error e, *err = &e;
  char cmd[4096];
  /* A decoder of the bundle's architecture that decodes differently. */
  char file[1024];
  snprintf(file, sizeof file, "%s/models/default/decoder.safetensors", testing_source_dir());
  model_decoder *dec = NULL;
  CHECK_OK(model_decoder_load(file, &dec, err), err);
  if (!dec) return;
  float *p = nn_params(dec->nn);
  size_t n_params = nn_param_count(dec->nn);
  for (size_t k = 0; k < n_params; k += 5)
    p[k] *= 0.8f;
  CHECK_OK(model_decoder_save(dec, path("dec.safetensors"), NULL, err), err);

  /* A 6 x 4 texture with a roughness gradient: 3 levels, distinct texels. */
  snprintf(cmd, sizeof cmd,
           "cd '%s' && oiiotool --pattern fill:left=0.1:right=0.6 6x4 1 -d uint8 -o alpha1.png && "
           "'%s' bake --bundle '%s/models/default' --alpha1 alpha1.png --eta 1.4 --alpha2 0.3 "
           "--r0 0.9,0.6,0.4 --albedo 0.6 --sigma-t 1 --decoder dec.safetensors -o v2.exr "
           ">/dev/null",
           tmp, cli_bin(), testing_source_dir());
  CHECK_MSG(system(cmd) == 0, "bake failed: %s", cmd);

  nbrdf_model *m = NULL;
  texture_latent_image *img = NULL;
  CHECK_OK(texture_latent_image_load_model(path("v2.exr"), bundle, &img, &m, err), err);
  if (!img) {
    model_decoder_destroy(dec);
    return;
  }
  CHECK(img->levels == 3 && img->width[0] == 6 && img->height[0] == 4);

  for (int level = 0; level < 2; level++) {
    int w = img->width[level], h = img->height[level];
    query q[64];
    int n = 0;
    for (int j = 0; j < h; j++)
      for (int i = 0; i < w; i++)
        q[n] = (query){(i + 0.5) / w, (j + 0.5) / h, n % N_DIRS}, n++;
    /* Between centres, at the edges (repeat wrapping) and the corners. */
    q[n++] = (query){0.3, 0.55, 0};
    q[n++] = (query){0.0, 0.0, 2};
    q[n++] = (query){1.0, 0.77, 3};
    double f[64 * 3];
    float want[64 * 3], bundle_f[64 * 3];
    CHECK(run_eval(path("v2.exr"), level, q, n, f) == n);
    reference(m, img, level, q, n, want);
    reference(bundle, img, level, q, n, bundle_f);
    int differ = 0;
    for (int k = 0; k < 3 * n; k++) {
      CHECK_MSG(close_to(f[k], want[k]), "level %d query %d channel %d: eval %.9g, library %.9g",
                level, k / 3, k % 3, f[k], (double)want[k]);
      differ += !close_to(f[k], bundle_f[k]);
    }
    CHECK_MSG(differ > 3 * n / 2, "level %d: only %d of %d values differ from the bundle's", level,
              differ, 3 * n);
  }
  /* At a texel centre the fetch is the texel itself: the texel as read by
   * the reader, decoded, is eval's value too. */
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, path("v2.exr"), err), err);
  if (r) {
    float texel[3 * 34], lat[3 * 32], wi[3], wo[3], fl[3];
    CHECK_OK(texture_latent_reader_read(r, 0, 4, 1, 1, 1, texel, err), err);
    texture_latent_reader_close(r);
    for (int c = 0; c < 3; c++)
      memcpy(lat + 32 * c, texel + texture_latent_index_latent(&img->layout, c, 0), 32 * 4);
    direction(DIRS[2], wi, wo);
    CHECK_OK(nbrdf_model_decode(m, 1, 3, lat, wi, wo, fl, err), err);
    query q = {4.5 / 6, 1.5 / 4, 2};
    double f[3];
    CHECK(run_eval(path("v2.exr"), 0, &q, 1, f) == 1);
    for (int c = 0; c < 3; c++)
      CHECK_MSG(close_to(f[c], fl[c]), "texel (4, 1) channel %d: eval %.9g, reader + decode %.9g",
                c, f[c], (double)fl[c]);
  }

  /* The packer given the texture's model packs the embedded weights. */
  size_t nw = 0;
  CHECK_OK(nbrdf_gpu_pack_decoder(m, NULL, 0, &nw, err), err);
  uint32_t *words = malloc(sizeof(uint32_t) * nw);
  CHECK_OK(nbrdf_gpu_pack_decoder(m, words, nw, NULL, err), err);
  if (words) {
    uint32_t at = words[NBRDF_GPU_W_PARAMS];
    CHECK(words[NBRDF_GPU_W_PARAM_COUNT] == n_params && at + n_params == nw);
    CHECK(at + n_params <= nw && !memcmp(words + at, p, n_params * sizeof(float)));
  }
  free(words);
  model_decoder_destroy(dec);
  nbrdf_model_destroy(m);
  texture_latent_image_free(img);
}

/* The committed version-1 texture: decoded with its bundle's decoder. */
static void test_v1(void) {
  nbrdf_error e, *err = &e;
  char file[1024], dir[1024];
  snprintf(file, sizeof file, "%s/tests/cli/data/v1_constant_rgb.exr", testing_source_dir());
  snprintf(dir, sizeof dir, "%s/models/v1", testing_source_dir());
  nbrdf_model *v1 = NULL, *m = NULL;
  CHECK_OK(nbrdf_model_load(dir, &v1, err), err);
  if (!v1) return;
  texture_latent_image *img = NULL;
  CHECK_OK(texture_latent_image_load_model(file, v1, &img, &m, err), err);
  if (!img) {
    nbrdf_model_destroy(v1);
    return;
  }
  nbrdf_decoder_info info;
  nbrdf_model_own_decoder(m, &info);
  CHECK(!info.own);
  query q[N_DIRS];
  for (int d = 0; d < N_DIRS; d++)
    q[d] = (query){0.25 * d, 0.5, d};
  double f[N_DIRS * 3];
  float want[N_DIRS * 3];
  eval_bundle = "models/v1";
  CHECK(run_eval(file, 0, q, N_DIRS, f) == N_DIRS);
  eval_bundle = "models/default";
  reference(v1, img, 0, q, N_DIRS, want);
  for (int k = 0; k < 3 * N_DIRS; k++)
    CHECK_MSG(close_to(f[k], want[k]), "query %d channel %d: eval %.9g, library %.9g", k / 3, k % 3,
              f[k], (double)want[k]);
  nbrdf_model_destroy(m);
  nbrdf_model_destroy(v1);
  texture_latent_image_free(img);
}

int main(void) {
  nbrdf_error e, *err = &e;
  snprintf(tmp, sizeof tmp, "%s", testing_tmpdir());
  char dir[1024];
  snprintf(dir, sizeof dir, "%s/models/default", testing_source_dir());
  CHECK_OK(nbrdf_model_load(dir, &bundle, err), err);
  if (!bundle) return testing_finish();
  RUN(test_own_decoder);
  RUN(test_v1);
  nbrdf_model_destroy(bundle);
  return testing_finish();
}
