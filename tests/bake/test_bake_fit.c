/* One fit per material (nbrdf/fit.h): a fit kept in a .nbfit file and baked
 * from gives the texels of the one-call bake, bit for bit (the same scene
 * gives the same selection and fit, and the evaluate stage then runs the same
 * networks on the same inputs in the same batch shapes); a fit over two tiles
 * gathers the tuples of both and gives both textures one decoder (the same
 * nbrdf:decoderChecksum) and one fit (the same fit= in nbrdf:accuracy); a bake
 * refuses a fit made with another bundle, other options or from other maps,
 * and a missing, damaged or foreign .nbfit; a cancelled fit leaves no file. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "model/bundle.h"
#include "nbrdf/bake.h"
#include "nbrdf/fit.h"
#include "testing.h"
#include "texture/latent_exr.h"
#include "texture/oiio_shim.h"

static nbrdf_model *model, *other_model;
static char tile_path[2][1024]; /* testing_path's buffer is reused: the maps' own copies */

/* alpha1 maps of two 8 x 8 tiles: two distinct values each, none shared. */
static void write_tiles(void) {
  nbrdf_error e, *err = &e;
  float a[64], b[64];
  for (int i = 0; i < 64; i++) {
    a[i] = (i % 8) < 4 ? 0.1f : 0.2f;
    b[i] = (i % 8) < 4 ? 0.4f : 0.5f;
  }
  snprintf(tile_path[0], sizeof tile_path[0], "%s", testing_path("a.1001.exr"));
  snprintf(tile_path[1], sizeof tile_path[1], "%s", testing_path("a.1002.exr"));
  CHECK_OK(texture_image_write(tile_path[0], 8, 8, 1, a, NBRDF_PIXEL_FLOAT, err), err);
  CHECK_OK(texture_image_write(tile_path[1], 8, 8, 1, b, NBRDF_PIXEL_FLOAT, err), err);
}

static nbrdf_bake_inputs tile(int n) {
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  const float v[NBRDF_BAKE_PARAM_COUNT] = {0.0f, 1.5f, 0.3f, 0.9f, 0.8f, 1.0f};
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    nbrdf_bake_param_constant(&in.param[id], v[id]);
  in.param[NBRDF_BAKE_ALPHA1].path = tile_path[n - 1];
  return in;
}

static nbrdf_bake_options options(nbrdf_bake_accuracy level) {
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.accuracy = level;
  o.budget = level == NBRDF_BAKE_COMPACT ? 6.0 : 2.0;
  o.compact_dim = 4;
  o.storage = NBRDF_BAKE_FLOAT;
  o.tile_size = 8;
  return o;
}

/* Every level-0 texel of a texture (malloc'ed), and its header's decoder checksum and
 * accuracy attribute. */
static float *texels(const char *name, size_t *n, char sum[17], char *acc, size_t cap) {
  nbrdf_error e, *err = &e;
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, testing_path(name), err), err);
  if (!r) return NULL;
  const texture_latent_info *info = texture_latent_reader_info(r);
  *n = (size_t)info->width * info->height * info->channels;
  float *t = malloc(sizeof *t * *n);
  CHECK_OK(texture_latent_reader_read(r, 0, 0, 0, info->width, info->height, t, err), err);
  snprintf(sum, 17, "%s", info->decoder_checksum);
  snprintf(acc, cap, "%s", info->accuracy);
  texture_latent_reader_close(r);
  return t;
}

/* fit + bake with it == the one-call bake, at each level that fits. */
static void test_same_texels(nbrdf_bake_accuracy level) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = tile(1);
  nbrdf_bake_options o = options(level);
  nbrdf_bake_report one, two;
  CHECK_OK(nbrdf_bake(model, &in, &o, testing_path("one.exr"), &one, err), err);
  nbrdf_fit_info info;
  CHECK_OK(nbrdf_fit_run(model, &in, 1, &o, testing_path("one.nbfit"), &info, err), err);
  CHECK(info.accuracy == level && info.tiles == 1 && info.distinct == 2);
  nbrdf_fit *fit = NULL;
  CHECK_OK(nbrdf_fit_open(testing_path("one.nbfit"), &fit, err), err);
  if (!fit) return;
  o.fit = fit;
  o.accuracy = NBRDF_BAKE_FAST; /* the fit's level */
  o.budget = 0.0;
  CHECK_OK(nbrdf_bake(model, &in, &o, testing_path("two.exr"), &two, err), err);
  CHECK(two.accuracy == level && two.heldout_error == one.heldout_error &&
        two.fitted_tuples == one.fitted_tuples && two.distinct == one.distinct);
  size_t n1 = 0, n2 = 0;
  char s1[17], s2[17], a1[600], a2[600];
  float *t1 = texels("one.exr", &n1, s1, a1, sizeof a1);
  float *t2 = texels("two.exr", &n2, s2, a2, sizeof a2);
  CHECK_MSG(t1 && t2 && n1 == n2 && !memcmp(t1, t2, sizeof *t1 * n1),
            "%s: texels of the bake with the fit differ from the one-call bake's",
            nbrdf_bake_accuracy_name(level));
  CHECK_MSG(!strcmp(s1, s2) && !strcmp(s2, info.decoder_checksum),
            "decoder checksums %s, %s, fit %s", s1, s2, info.decoder_checksum);
  CHECK(level == NBRDF_BAKE_FITTED ? !s1[0] : s1[0] != 0);
  /* The same attribute, and the fit named after it. */
  CHECK_MSG(!strncmp(a1, a2, strlen(a1)) && strstr(a2, "; fit=") &&
                !strcmp(strstr(a2, "; fit=") + 6, info.file_checksum),
            "accuracy '%s' vs '%s'", a1, a2);
  free(t1), free(t2);
  nbrdf_fit_destroy(fit);
}

static void test_levels(void) {
  test_same_texels(NBRDF_BAKE_FITTED);
  test_same_texels(NBRDF_BAKE_SPECIALISED);
  test_same_texels(NBRDF_BAKE_COMPACT);
}

/* A fit over two tiles: the tuples of both, one decoder in both textures. */
static void test_two_tiles(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs tiles[2] = {tile(1), tile(2)};
  nbrdf_bake_options o = options(NBRDF_BAKE_SPECIALISED);
  nbrdf_fit_info info;
  CHECK_OK(nbrdf_fit_run(model, tiles, 2, &o, testing_path("set.nbfit"), &info, err), err);
  CHECK_MSG(info.tiles == 2 && info.distinct == 4, "tiles %d, distinct %zu", info.tiles,
            info.distinct);
  nbrdf_fit *fit = NULL;
  CHECK_OK(nbrdf_fit_open(testing_path("set.nbfit"), &fit, err), err);
  if (!fit) return;
  o.fit = fit;
  CHECK_OK(nbrdf_bake(model, &tiles[0], &o, testing_path("set.1001.exr"), NULL, err), err);
  CHECK_OK(nbrdf_bake(model, &tiles[1], &o, testing_path("set.1002.exr"), NULL, err), err);
  size_t n;
  char s1[17], s2[17], a1[600], a2[600];
  free(texels("set.1001.exr", &n, s1, a1, sizeof a1));
  free(texels("set.1002.exr", &n, s2, a2, sizeof a2));
  CHECK_MSG(s1[0] && !strcmp(s1, s2) && !strcmp(s1, info.decoder_checksum),
            "tiles' decoders %s and %s, fit's %s", s1, s2, info.decoder_checksum);
  CHECK_MSG(!strcmp(a1, a2) && strstr(a1, "distinct=4;"), "accuracy '%s' vs '%s'", a1, a2);
  /* Each tile baked on its own fits its own decoder. */
  nbrdf_bake_options own = options(NBRDF_BAKE_SPECIALISED);
  CHECK_OK(nbrdf_bake(model, &tiles[1], &own, testing_path("own.1002.exr"), NULL, err), err);
  free(texels("own.1002.exr", &n, s2, a2, sizeof a2));
  CHECK_MSG(strcmp(s1, s2) != 0, "a tile's own fit has the set's decoder %s", s2);
  nbrdf_fit_destroy(fit);
}

static void test_refusals(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = tile(1);
  nbrdf_bake_options o = options(NBRDF_BAKE_SPECIALISED);
  CHECK_OK(nbrdf_fit_run(model, &in, 1, &o, testing_path("r.nbfit"), NULL, err), err);
  nbrdf_fit *fit = NULL;
  CHECK_OK(nbrdf_fit_open(testing_path("r.nbfit"), &fit, err), err);
  if (!fit) return;
  o.fit = fit;
  const char *out = testing_path("refused.exr");
  CHECK_FAILS(nbrdf_bake(other_model, &in, &o, out, NULL, err), NBRDF_ERR_MISMATCH, err,
              "fitted with the bundle of checksum");
  CHECK(strstr(e.message, "r.nbfit") != NULL);
  o.roughness = NBRDF_ROUGHNESS_PERCEPTUAL;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, out, NULL, err), NBRDF_ERR_MISMATCH, err,
              "fitted with roughness alpha, but this bake has roughness");
  o.roughness = NBRDF_ROUGHNESS_ALPHA;
  o.quantise_bits = 8;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, out, NULL, err), NBRDF_ERR_MISMATCH, err,
              "quantise bits off, but this bake has quantise bits 8");
  o.quantise_bits = 0;
  o.range = NBRDF_RANGE_REFUSE;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, out, NULL, err), NBRDF_ERR_MISMATCH, err, "range clamp");
  o.range = NBRDF_RANGE_CLAMP;
  o.accuracy = NBRDF_BAKE_FITTED;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, out, NULL, err), NBRDF_ERR_MISMATCH, err,
              "accuracy specialised");
  o.accuracy = NBRDF_BAKE_SPECIALISED;
  nbrdf_bake_inputs b = tile(2);
  CHECK_FAILS(nbrdf_bake(model, &b, &o, out, NULL, err), NBRDF_ERR_MISMATCH, err,
              "the alpha1 map");
  CHECK(strstr(e.message, "a.1002.exr") && strstr(e.message, "fnv1a64="));
  nbrdf_bake_param_constant(&b.param[NBRDF_BAKE_ALPHA1], 0.1f);
  CHECK_FAILS(nbrdf_bake(model, &b, &o, out, NULL, err), NBRDF_ERR_MISMATCH, err,
              "the alpha1 constant 0.1");
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ETA], 1.6f);
  CHECK_FAILS(nbrdf_bake(model, &in, &o, out, NULL, err), NBRDF_ERR_MISMATCH, err,
              "the eta constant 1.6 is not among");
  struct stat sb;
  CHECK(stat(out, &sb) != 0);
  nbrdf_fit_destroy(fit);

  /* Files that are no fit. */
  CHECK_FAILS(nbrdf_fit_open(testing_path("missing.nbfit"), &fit, err), NBRDF_ERR_IO, err,
              "missing.nbfit");
  testing_write_text(testing_path("text.nbfit"), "not a fit\n");
  CHECK(nbrdf_fit_open(testing_path("text.nbfit"), &fit, err) == NBRDF_ERR_FORMAT && !fit);
  CHECK(strstr(e.message, "text.nbfit") != NULL);
  /* Truncated: the first half of a real one. */
  FILE *f = fopen(testing_path("r.nbfit"), "rb");
  char *bytes = malloc(1 << 22);
  size_t n = f ? fread(bytes, 1, 1 << 22, f) : 0;
  if (f) fclose(f);
  f = fopen(testing_path("half.nbfit"), "wb");
  if (f) fwrite(bytes, 1, n / 2, f), fclose(f);
  CHECK_FAILS(nbrdf_fit_open(testing_path("half.nbfit"), &fit, err), NBRDF_ERR_FORMAT, err,
              "half.nbfit");
  /* A decoder file is a safetensors file, but no fit. */
  char dec[1024];
  snprintf(dec, sizeof dec, "%s/bundle/decoder.safetensors", testing_tmpdir());
  CHECK_FAILS(nbrdf_fit_open(dec, &fit, err), NBRDF_ERR_FORMAT, err, "not a fit file");
  /* One flipped byte in a tensor: the decoders' checksum no longer matches. */
  for (size_t i = n - 1; i > n - 64; i--)
    bytes[i] ^= 0x01;
  f = fopen(testing_path("flipped.nbfit"), "wb");
  if (f) fwrite(bytes, 1, n, f), fclose(f);
  CHECK(nbrdf_fit_open(testing_path("flipped.nbfit"), &fit, err) != NBRDF_OK && !fit);
  free(bytes);
  /* A value the range policy refuses, in the second tile of a set: the message names its
   * map (the map reader names it for what no bake takes at all, a negative value). */
  float bad[64];
  for (int i = 0; i < 64; i++)
    bad[i] = i == 2 * 8 + 3 ? 50.0f : 0.1f;
  static char bad_path[1024];
  snprintf(bad_path, sizeof bad_path, "%s", testing_path("a.bad.exr"));
  CHECK_OK(texture_image_write(bad_path, 8, 8, 1, bad, NBRDF_PIXEL_FLOAT, err), err);
  nbrdf_bake_inputs set[2] = {tile(1), tile(1)};
  set[1].param[NBRDF_BAKE_ALPHA1].path = bad_path;
  o = options(NBRDF_BAKE_SPECIALISED);
  o.range = NBRDF_RANGE_REFUSE;
  CHECK(nbrdf_fit_run(model, set, 2, &o, testing_path("bad.nbfit"), NULL, err) != NBRDF_OK);
  CHECK_MSG(strstr(e.message, "alpha1 at texel (3, 2) of ") && strstr(e.message, "a.bad.exr"),
            "message '%s'", e.message);
  CHECK(stat(testing_path("bad.nbfit"), &sb) != 0);
  /* Fast has nothing to fit. */
  o = options(NBRDF_BAKE_FAST);
  CHECK_FAILS(nbrdf_fit_run(model, &in, 1, &o, testing_path("fast.nbfit"), NULL, err),
              NBRDF_ERR_ARGUMENT, err, "fast has nothing to fit");
}

static int cancel_in_fit(void *user, const char *stage, double done, double total) {
  (void)user, (void)total;
  return !strcmp(stage, "fit") && done >= 5;
}

static void test_cancel(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = tile(1);
  nbrdf_bake_options o = options(NBRDF_BAKE_SPECIALISED);
  o.progress = cancel_in_fit;
  CHECK_FAILS(nbrdf_fit_run(model, &in, 1, &o, testing_path("cancel.nbfit"), NULL, err),
              NBRDF_ERR_CANCELLED, err, "cancelled");
  struct stat sb;
  CHECK(stat(testing_path("cancel.nbfit"), &sb) != 0);
  size_t n = 0;
  char **left = testing_list_dir(testing_tmpdir(), &n);
  for (size_t i = 0; i < n; i++) {
    CHECK_MSG(!strstr(left[i], "cancel"), "left behind: %s", left[i]);
    free(left[i]);
  }
  free(left);
}

int main(int argc, char **argv) {
  testing_one_blas_thread(argc, argv);
  nbrdf_error e, *err = &e;
  char dir[1024];
  snprintf(dir, sizeof dir, "%s/bundle", testing_tmpdir());
  CHECK_OK(model_bundle_init_random(dir, "fit-test", 7, "small", err), err);
  CHECK_OK(nbrdf_model_load(dir, &model, err), err);
  snprintf(dir, sizeof dir, "%s/other", testing_tmpdir());
  CHECK_OK(model_bundle_init_random(dir, "fit-test", 8, "small", err), err);
  CHECK_OK(nbrdf_model_load(dir, &other_model, err), err);
  if (!model || !other_model) return testing_finish();
  write_tiles();
  RUN(test_levels);
  RUN(test_two_tiles);
  RUN(test_refusals);
  RUN(test_cancel);
  nbrdf_model_destroy(model);
  nbrdf_model_destroy(other_model);
  return testing_finish();
}
