/* Latent textures as other tools see them: OpenImageIO (through our shim,
 * every mip level, channels by name), `iinfo -v` and `exrheader`. */
#include <stdio.h>

#include "latent_fixture.h"
#include "texture/oiio_shim.h"

/* Runs a shell command and returns its stdout (caller frees), or NULL. */
static char *capture(const char *cmd) {
  FILE *p = popen(cmd, "r");
  if (!p) return NULL;
  size_t cap = 1 << 16, n = 0;
  char *buf = malloc(cap);
  for (size_t r; buf && (r = fread(buf + n, 1, cap - 1 - n, p)) > 0;) {
    n += r;
    if (n + 1 >= cap) {
      char *bigger = realloc(buf, cap *= 2);
      if (!bigger) break;
      buf = bigger;
    }
  }
  int status = pclose(p);
  if (buf) buf[n] = '\0';
  if (status != 0) {
    fprintf(stderr, "'%s' exited with %d\n", cmd, status);
    free(buf);
    return NULL;
  }
  return buf;
}

#define CHECK_HAS(text, needle)                                                                    \
  CHECK_MSG((text) && strstr((text), (needle)), "output lacks \"%s\"", (needle))

static void write_texture(const char *path, int W, int H, texture_latent_layout layout,
                          texture_latent_storage storage, int tile, float **l0_out) {
  nbrdf_error e, *err = &e;
  float *l0 = fixture_texels(W, H, &layout, (uint64_t)(W + 31 * H));
  texture_latent_exr_options opts = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  opts.storage = storage;
  opts.tile_size = tile;
  texture_latent_meta meta = {
      "nbrdf-test", "0123abcd", "alpha1=a.png; eta=1.5", "half; zip", NULL, 0, NULL, NULL};
  CHECK_OK(fixture_write(path, W, H, &layout, &meta, &opts, l0, 13, err), err);
  *l0_out = l0;
}

/* Every level through OpenImageIO equals every level through OpenEXRCore,
 * bit for bit, with OIIO's channels matched to ours by name. */
static void compare_with_oiio(const char *path) {
  nbrdf_error e, *err = &e;
  texture_latent_reader *r = NULL;
  texture_image_in *img = NULL;
  texture_image_info ii;
  CHECK_OK(texture_latent_reader_open(&r, path, err), err);
  CHECK_OK(texture_image_open(path, 0, &img, &ii, err), err);
  if (!r || !img) {
    texture_latent_reader_close(r);
    texture_image_close(img);
    return;
  }
  const texture_latent_info *in = texture_latent_reader_info(r);
  CHECK(ii.width == in->width && ii.height == in->height && ii.channels == in->channels);
  CHECK(ii.mip_levels == in->levels);
  int C = in->channels, *ours = malloc(sizeof(int) * (size_t)C), mapped = 1;
  for (int k = 0; k < C; k++) {
    ours[k] = texture_latent_channel_index(&in->layout, texture_image_channel_name(img, k));
    mapped &= ours[k] >= 0;
  }
  CHECK_MSG(mapped, "%s: OIIO names a channel we do not know", path);
  for (int l = 0; mapped && l < in->levels; l++) {
    int w = 0, h = 0, ow = 0, oh = 0;
    CHECK_OK(texture_latent_reader_level_size(r, l, &w, &h, err), err);
    CHECK_OK(texture_image_level_size(img, l, &ow, &oh, err), err);
    CHECK(w == ow && h == oh);
    float *a = malloc(sizeof(float) * (size_t)w * h * C),
          *b = malloc(sizeof(float) * (size_t)w * h * C);
    CHECK_OK(texture_latent_reader_read(r, l, 0, 0, w, h, a, err), err);
    CHECK_OK(texture_image_read_rows(img, l, 0, h, 0, C, b, err), err);
    size_t diff = 0;
    for (size_t p = 0; p < (size_t)w * h; p++)
      for (int k = 0; k < C; k++)
        diff += a[p * C + ours[k]] != b[p * C + k];
    CHECK_MSG(diff == 0, "%s level %d: %zu values differ between OpenEXRCore and OIIO", path, l,
              diff);
    free(a);
    free(b);
  }
  free(ours);
  texture_image_close(img);
  texture_latent_reader_close(r);
}

static void test_openimageio_reads_every_level(void) {
  static const int sizes[][2] = {{67, 45}, {300, 200}, {1, 1}, {1, 17}, {129, 64}};
  texture_latent_layout rgb = {4, NBRDF_COLOUR_RGB, 1}, mono = {3, NBRDF_COLOUR_MONO, 1};
  for (int i = 0; i < 5; i++)
    for (int s = 0; s < 4; s++) {
      char path[512];
      float *l0 = NULL;
      texture_latent_storage st = s & 1 ? NBRDF_LATENT_FLOAT : NBRDF_LATENT_HALF;
      snprintf(path, sizeof path, "%s/oiio_%d_%d.exr", testing_tmpdir(), i, s);
      write_texture(path, sizes[i][0], sizes[i][1], s & 2 ? mono : rgb, st, 16, &l0);
      compare_with_oiio(path);
      free(l0);
    }
}

static void test_iinfo_and_exrheader(void) {
  char path[512], cmd[700];
  float *l0 = NULL;
  snprintf(path, sizeof path, "%s/tools.exr", testing_tmpdir());
  write_texture(path, 67, 45, (texture_latent_layout){32, NBRDF_COLOUR_RGB, 1}, NBRDF_LATENT_HALF,
                64, &l0);
  free(l0);
  snprintf(cmd, sizeof cmd, "iinfo -v '%s' 2>&1", path);
  char *out = capture(cmd);
  CHECK_MSG(out != NULL, "iinfo failed");
  CHECK_HAS(out, "67 x   45, 102 channel, half openexr");
  CHECK_HAS(out, "MIP-map levels: 67x45 33x22 16x11 8x5 4x2 2x1 1x1");
  CHECK_HAS(out, "latent.L00.R");
  CHECK_HAS(out, "proxy.sigma.B");
  CHECK_HAS(out, "nbrdf:modelChecksum: \"0123abcd\"");
  free(out);

  snprintf(cmd, sizeof cmd, "exrheader '%s' 2>&1", path);
  out = capture(cmd);
  CHECK_MSG(out != NULL, "exrheader failed");
  CHECK_HAS(out, "latent.L31.G, 16-bit floating-point, sampling 1 1");
  CHECK_HAS(out, "proxy.w.R, 16-bit floating-point");
  CHECK_HAS(out, "lineOrder (type lineOrder): random y");
  CHECK_HAS(out, "mip-map");
  CHECK_HAS(out, "level sizes rounded down");
  CHECK_HAS(out, "nbrdf:formatVersion (type int): 1");
  CHECK_HAS(out, "nbrdf:colourMode (type string): \"rgb\"");
  CHECK_HAS(out, "nbrdf:latentDim (type int): 32");
  CHECK_HAS(out, "nbrdf:parameterSources (type string): \"alpha1=a.png; eta=1.5\"");
  free(out);
}

int main(void) {
  RUN(test_openimageio_reads_every_level);
  RUN(test_iinfo_and_exrheader);
  return testing_finish();
}
