/* Latent texture format version 2: a texture carrying its own decoder.
 * A bake with a model whose decoder was replaced (the default decoder with
 * perturbed weights) writes a version-2 file; it reads back with that
 * decoder (decodes equal to it, different from the bundle's), the GPU packer
 * gets the same decoder, version 1 is still written byte for byte as before
 * and still read, and damaged or dropped decoders are refused naming the file. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "model/bundle.h"
#include "nbrdf/bake.h"
#include "nbrdf/gpu_pack.h"
#include "nbrdf/nbrdf.h"
#include "testing.h"
#include "texture/latent_exr.h"

static nbrdf_model *bundle;

static unsigned char *read_all(const char *p, size_t *n) {
  FILE *f = fopen(p, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long len = ftell(f);
  fseek(f, 0, SEEK_SET);
  unsigned char *b = malloc((size_t)len + 1);
  *n = b ? fread(b, 1, (size_t)len, f) : 0;
  fclose(f);
  return b;
}

static unsigned char *find(unsigned char *hay, size_t n, const unsigned char *needle, size_t m) {
  for (size_t i = 0; i + m <= n; i++)
    if (!memcmp(hay + i, needle, m)) return hay + i;
  return NULL;
}

static int write_all(const char *p, const void *b, size_t n) {
  FILE *f = fopen(p, "wb");
  if (!f) return 0;
  int ok = fwrite(b, 1, n, f) == n;
  return fclose(f) == 0 && ok;
}

/* The bundle's decoder with every 7th weight scaled by 1.25: a decoder of
 * the same architecture that decodes visibly differently. */
static nbrdf_model *perturbed_model(void) {
  model_decoder *dec = NULL;
  nbrdf_error e, *err = &e;
  char file[1024];
  snprintf(file, sizeof file, "%s/models/default/decoder.safetensors", testing_source_dir());
  CHECK_OK(model_decoder_load(file, &dec, err), err);
  if (!dec) return NULL;
  float *p = nn_params(dec->nn);
  for (size_t k = 0; k < nn_param_count(dec->nn); k += 7)
    p[k] *= 1.25f;
  nbrdf_model *m = NULL;
  CHECK_OK(model_with_decoder_net(bundle, dec, &m, err), err);
  model_decoder_destroy(dec);
  return m;
}

static nbrdf_bake_inputs constant_rgb(void) {
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA1], 0.3f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ETA], 1.5f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA2], 0.2f);
  nbrdf_bake_param r0 = {NULL, {0.9f, 0.6f, 0.3f}, 3, NULL, 0, 0.0f, 1.0f};
  in.param[NBRDF_BAKE_R0] = r0;
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALBEDO], 0.5f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_SIGMA_T], 1.0f);
  return in;
}

/* f of texel (0, 0) of `tex`, 3 colour channels, at a few direction pairs. */
#define NQ 4
static void decode_texel(const nbrdf_model *m, const char *tex, float f[NQ * 3]) {
  nbrdf_error e, *err = &e;
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, tex, err), err);
  if (!r) return;
  const texture_latent_info *info = texture_latent_reader_info(r);
  float texel[3 * 34];
  CHECK(info->channels == 3 * 34);
  CHECK_OK(texture_latent_reader_read(r, 0, 0, 0, 1, 1, texel, err), err);
  texture_latent_reader_close(r);
  float lat[NQ * 3 * 32], wi[NQ * 3], wo[NQ * 3];
  for (int q = 0; q < NQ; q++) {
    float ti = 0.2f + 0.3f * (float)q, to = 0.5f;
    wi[3 * q] = sinf(ti), wi[3 * q + 1] = 0.0f, wi[3 * q + 2] = cosf(ti);
    wo[3 * q] = -sinf(to), wo[3 * q + 1] = 0.0f, wo[3 * q + 2] = cosf(to);
    for (int c = 0; c < 3; c++)
      memcpy(lat + (q * 3 + c) * 32, texel + c * 34, 32 * sizeof(float));
  }
  CHECK_OK(nbrdf_model_decode(m, NQ, 3, lat, wi, wo, f, err), err);
}

static uint32_t *pack(const nbrdf_model *m, size_t *n) {
  nbrdf_error e, *err = &e;
  CHECK_OK(nbrdf_gpu_pack_decoder(m, NULL, 0, n, err), err);
  uint32_t *w = malloc(sizeof(uint32_t) * *n);
  CHECK_OK(nbrdf_gpu_pack_decoder(m, w, *n, NULL, err), err);
  return w;
}

static void test_round_trip(void) {
  nbrdf_error e, *err = &e;
  nbrdf_model *own = perturbed_model();
  if (!own) return;
  nbrdf_decoder_info di, bi;
  nbrdf_model_own_decoder(own, &di);
  nbrdf_model_own_decoder(bundle, &bi);
  CHECK(di.own && di.size > 1000 && di.bytes && strlen(di.checksum) == 16);
  CHECK(!bi.own && bi.size == 0 && !bi.bytes && bi.checksum[0] == '\0');
  /* The bundle's identity is kept: textures record the bundle's checksum. */
  CHECK(!strcmp(nbrdf_model_checksum(own), nbrdf_model_checksum(bundle)));

  nbrdf_bake_inputs in = constant_rgb();
  CHECK_OK(nbrdf_bake(own, &in, NULL, testing_path("v2.exr"), NULL, err), err);
  CHECK_OK(nbrdf_bake(bundle, &in, NULL, testing_path("v1.exr"), NULL, err), err);

  nbrdf_decoder_info t2, t1;
  CHECK_OK(nbrdf_texture_own_decoder(testing_path("v2.exr"), &t2, err), err);
  CHECK_OK(nbrdf_texture_own_decoder(testing_path("v1.exr"), &t1, err), err);
  CHECK(t2.own && t2.size == di.size && !strcmp(t2.checksum, di.checksum) && !t2.bytes);
  CHECK(!t1.own && t1.size == 0);
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, testing_path("v2.exr"), err), err);
  if (r) {
    CHECK(texture_latent_reader_info(r)->format_version == 2);
    size_t n = 0;
    const void *b = texture_latent_reader_decoder(r, &n);
    CHECK(b && n == di.size && !memcmp(b, di.bytes, n));
    texture_latent_reader_close(r);
  }
  CHECK_OK(texture_latent_reader_open(&r, testing_path("v1.exr"), err), err);
  if (r) CHECK(texture_latent_reader_info(r)->format_version == 1);
  texture_latent_reader_close(r);

  /* The texture's model decodes as the embedded decoder, not as the bundle's. */
  nbrdf_model *m2 = NULL, *m1 = NULL;
  CHECK_OK(nbrdf_model_for_texture(bundle, testing_path("v2.exr"), &m2, err), err);
  CHECK_OK(nbrdf_model_for_texture(bundle, testing_path("v1.exr"), &m1, err), err);
  if (!m2 || !m1) return;
  nbrdf_decoder_info i2, i1;
  nbrdf_model_own_decoder(m2, &i2);
  nbrdf_model_own_decoder(m1, &i1);
  CHECK(i2.own && !strcmp(i2.checksum, di.checksum) && !i1.own);
  float f_tex[NQ * 3], f_own[NQ * 3], f_bundle[NQ * 3], f_m1[NQ * 3];
  decode_texel(m2, testing_path("v2.exr"), f_tex);
  decode_texel(own, testing_path("v2.exr"), f_own);
  decode_texel(bundle, testing_path("v2.exr"), f_bundle);
  decode_texel(m1, testing_path("v2.exr"), f_m1);
  double diff = 0;
  for (int k = 0; k < NQ * 3; k++) {
    CHECK(f_tex[k] == f_own[k]);
    CHECK(f_m1[k] == f_bundle[k]);
    diff += fabs((double)f_tex[k] - f_bundle[k]) / (1e-3 + fabs((double)f_bundle[k]));
  }
  CHECK_MSG(diff / (NQ * 3) > 0.01, "the perturbed decoder decodes like the bundle's (%g)",
            diff / (NQ * 3));

  /* The GPU packer of the texture's model packs the embedded decoder. */
  size_t n2, no, nb;
  uint32_t *w2 = pack(m2, &n2), *wo = pack(own, &no), *wb = pack(bundle, &nb);
  CHECK(n2 == no && n2 == nb && !memcmp(w2, wo, n2 * 4) && memcmp(w2, wb, n2 * 4) != 0);
  free(w2), free(wo), free(wb);

  /* A derived model outlives the bundle handle it came from. */
  nbrdf_model *again = NULL;
  CHECK_OK(nbrdf_model_for_texture(m2, testing_path("v2.exr"), &again, err), err);
  nbrdf_model_destroy(m2);
  nbrdf_model_destroy(m1);
  nbrdf_model_destroy(own);
  if (again) {
    float f_again[NQ * 3];
    decode_texel(again, testing_path("v2.exr"), f_again);
    CHECK(!memcmp(f_again, f_tex, sizeof f_tex));
  }
  nbrdf_model_destroy(again);
}

/* Version 1 is written exactly as before version 2 existed: the committed
 * texture (a bake of constant_rgb() with models/default, now models/v1, by nbrdf 0.1.0, before
 * version 2) rewritten through the writer without a decoder gives its bytes. */
static void test_v1_bytes_unchanged(void) {
  nbrdf_error e, *err = &e;
  char file[1024];
  snprintf(file, sizeof file, "%s/tests/cli/data/v1_constant_rgb.exr", testing_source_dir());
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, file, err), err);
  if (!r) return;
  const texture_latent_info *in = texture_latent_reader_info(r);
  CHECK(in->format_version == 1 && in->decoder_size == 0 && !strcmp(in->decoder_checksum, ""));
  char writer[64];
  snprintf(writer, sizeof writer, "nbrdf %s", nbrdf_version());
  /* The writer attribute holds the version: a new version needs a new file
   * (the bake command is in docs/LATENT-TEXTURE.md, "Format versions"). */
  CHECK_MSG(!strcmp(in->writer, writer), "%s was written by '%s', this is '%s': re-bake it", file,
            in->writer, writer);
  CHECK(in->width == 1 && in->height == 1 && in->levels == 1);
  float *texel = malloc(sizeof(float) * (size_t)in->channels);
  CHECK_OK(texture_latent_reader_read(r, 0, 0, 0, 1, 1, texel, err), err);
  texture_latent_meta meta = {
      in->model_name, in->model_checksum, in->sources, in->settings, NULL, 0, NULL, NULL};
  texture_latent_exr_options o = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  texture_latent_writer *w = NULL;
  CHECK_OK(texture_latent_writer_create(&w, testing_path("rewritten.exr"), 1, 1, &in->layout, &meta, &o,
                                        NULL, 0, err),
           err);
  if (w) CHECK_OK(texture_latent_writer_write_rows(w, texel, 1, err), err);
  if (w) CHECK_OK(texture_latent_writer_finish(w, err), err);
  texture_latent_reader_close(r);
  free(texel);
  size_t na = 0, nb = 0;
  unsigned char *a = read_all(file, &na), *b = read_all(testing_path("rewritten.exr"), &nb);
  CHECK_MSG(a && b && na == nb && !memcmp(a, b, na), "version-1 bytes changed (%zu vs %zu bytes)",
            na, nb);
  free(a), free(b);

  /* And its bundle (models/v1, the default until 2026-11-26) reads it with
   * the bundle's decoder, as before; today's default refuses it, naming both. */
  char dir[1024];
  snprintf(dir, sizeof dir, "%s/models/v1", testing_source_dir());
  nbrdf_model *v1 = NULL, *m = NULL;
  CHECK_OK(nbrdf_model_load(dir, &v1, err), err);
  if (v1) CHECK_OK(nbrdf_model_for_texture(v1, file, &m, err), err);
  nbrdf_decoder_info i;
  if (m) nbrdf_model_own_decoder(m, &i);
  CHECK(m && !i.own);
  nbrdf_model_destroy(m);
  nbrdf_model_destroy(v1);
  m = NULL;
  CHECK(nbrdf_model_for_texture(bundle, file, &m, err) == NBRDF_ERR_MISMATCH && !m);
  CHECK_MSG(strstr(err->message, "baked with model 'default' (checksum 0ab22d273b6be904)") &&
                strstr(err->message, "with the bundle of that checksum"),
            "%s", err->message);
}

/* Writes a 1x1 texture of the bundle whose "decoder" is `bytes`. */
static void write_with_decoder(const char *p, const void *bytes, size_t size) {
  nbrdf_error e, *err = &e;
  texture_latent_layout layout = {32, NBRDF_COLOUR_MONO, 1};
  texture_latent_meta meta = {nbrdf_model_name(bundle), nbrdf_model_checksum(bundle), "", "",
                            bytes, size, NULL, NULL};
  float texel[34] = {0};
  texel[32] = 0.5f;
  texture_latent_writer *w = NULL;
  CHECK_OK(texture_latent_writer_create(&w, p, 1, 1, &layout, &meta, NULL, NULL, 0, err), err);
  if (w) CHECK_OK(texture_latent_writer_write_rows(w, texel, 1, err), err);
  if (w) CHECK_OK(texture_latent_writer_finish(w, err), err);
}

static void expect_refused(const char *p, const char *needle) {
  nbrdf_error e, *err = &e;
  nbrdf_model *m = NULL;
  CHECK_FAILS(nbrdf_model_for_texture(bundle, p, &m, err), NBRDF_ERR_FORMAT, err, needle);
  CHECK_MSG(strstr(err->message, p) == err->message, "'%s' does not start with the file name",
            err->message);
  CHECK(m == NULL);
}

static void test_damaged_decoders(void) {
  nbrdf_error e, *err = &e;
  char file[1024];
  snprintf(file, sizeof file, "%s/models/default/decoder.safetensors", testing_source_dir());
  size_t n = 0;
  unsigned char *bytes = read_all(file, &n);
  CHECK(bytes && n > 4096);
  if (!bytes) return;

  /* A byte changed inside the embedded bytes: the checksum no longer matches. */
  write_with_decoder(testing_path("good.exr"), bytes, n);
  size_t fn = 0;
  unsigned char *tex = read_all(testing_path("good.exr"), &fn);
  unsigned char *at = tex ? find(tex, fn, bytes + 2048, 64) : NULL;
  CHECK(at != NULL);
  if (at) {
    at[10] ^= 0x40;
    CHECK(write_all(testing_path("flipped.exr"), tex, fn));
    expect_refused(testing_path("flipped.exr"), "the embedded decoder is damaged");
    nbrdf_decoder_info i;
    CHECK_FAILS(nbrdf_texture_own_decoder(testing_path("flipped.exr"), &i, err), NBRDF_ERR_FORMAT, err,
                "is damaged");
  }
  free(tex);

  /* Right checksum, but not safetensors. */
  write_with_decoder(testing_path("text.exr"), "this is not a safetensors file", 30);
  expect_refused(testing_path("text.exr"), "embedded decoder (nbrdf:decoder)");
  /* A layering network where the decoder belongs. */
  char layering[1024];
  snprintf(layering, sizeof layering, "%s/models/default/sampler.safetensors",
           testing_source_dir());
  size_t ln = 0;
  unsigned char *lb = read_all(layering, &ln);
  write_with_decoder(testing_path("sampler.exr"), lb, ln);
  expect_refused(testing_path("sampler.exr"), "embedded decoder");
  free(lb);
  /* A decoder for latents of another size than the texture's: refused. A decoder of
   * fewer latents than the bundle's is a compact one (issue 19) and makes a model of
   * that size; one of more is refused. */
  model_decoder_config cfg;
  model_decoder *d16 = NULL, *d64 = NULL;
  void *b16 = NULL, *b64 = NULL;
  size_t n16 = 0, n64 = 0;
  CHECK_OK(model_decoder_preset("small", 16, &cfg, err), err);
  CHECK_OK(model_decoder_create(&cfg, 3, &d16, err), err);
  CHECK_OK(model_decoder_serialize(d16, &b16, &n16, err), err);
  write_with_decoder(testing_path("dim16.exr"), b16, n16);
  expect_refused(testing_path("dim16.exr"), "decodes latents of 16 floats, the texture's have 32");
  nbrdf_model *m = NULL;
  CHECK_OK(nbrdf_model_with_decoder(bundle, b16, n16, "d16.safetensors", &m, err), err);
  CHECK(m && nbrdf_model_latent_dim(m) == 16);
  float lat[16] = {0}, sg, wg;
  if (m)
    CHECK_FAILS(nbrdf_model_proxy_params(m, 1, lat, &sg, &wg, err), NBRDF_ERR_UNSUPPORTED, err,
                "compact texture's 16 latent channels");
  nbrdf_model_destroy(m);
  m = NULL;
  CHECK_OK(model_decoder_preset("small", 64, &cfg, err), err);
  CHECK_OK(model_decoder_create(&cfg, 3, &d64, err), err);
  CHECK_OK(model_decoder_serialize(d64, &b64, &n64, err), err);
  CHECK_FAILS(nbrdf_model_with_decoder(bundle, b64, n64, "d64.safetensors", &m, err),
              NBRDF_ERR_MISMATCH, err,
              "d64.safetensors: the decoder has latent dimension 64, more than the bundle");
  model_decoder_destroy(d16), model_decoder_destroy(d64);
  free(b16), free(b64);

  /* More than 64 MiB is refused before anything is written or read. */
  texture_latent_layout layout = {32, NBRDF_COLOUR_MONO, 1};
  texture_latent_meta big = {"m", "c", "", "", bytes, NBRDF_DECODER_BYTES_MAX + 1, NULL, NULL};
  texture_latent_writer *w = NULL;
  CHECK_FAILS(
      texture_latent_writer_create(&w, testing_path("big.exr"), 1, 1, &layout, &big, NULL, NULL, 0, err),
      NBRDF_ERR_ARGUMENT, err, "it must have 1 byte to 64 MiB");
  struct stat sb;
  CHECK(w == NULL && stat(testing_path("big.exr"), &sb) != 0);
  CHECK_FAILS(nbrdf_model_with_decoder(bundle, bytes, NBRDF_DECODER_BYTES_MAX + 1, "big", &m, err),
              NBRDF_ERR_ARGUMENT, err, "big: 67108865 bytes, more than the 64 MiB");
  /* Exactly 64 MiB is written and read back (OpenEXR holds attributes that large). */
  unsigned char *huge = calloc(NBRDF_DECODER_BYTES_MAX, 1);
  if (huge) {
    huge[12345] = 7;
    write_with_decoder(testing_path("huge.exr"), huge, NBRDF_DECODER_BYTES_MAX);
    texture_latent_reader *r = NULL;
    CHECK_OK(texture_latent_reader_open(&r, testing_path("huge.exr"), err), err);
    size_t hn = 0;
    const unsigned char *hb = r ? texture_latent_reader_decoder(r, &hn) : NULL;
    CHECK(hb && hn == NBRDF_DECODER_BYTES_MAX && hb[12345] == 7 && hb[12346] == 0);
    texture_latent_reader_close(r);
    expect_refused(testing_path("huge.exr"), "embedded decoder");
    remove(testing_path("huge.exr"));
    free(huge);
  }
  free(bytes);
}

int main(void) {
  nbrdf_error e, *err = &e;
  char dir[1024];
  snprintf(dir, sizeof dir, "%s/models/default", testing_source_dir());
  CHECK_OK(nbrdf_model_load(dir, &bundle, err), err);
  if (!bundle) return testing_finish();
  RUN(test_round_trip);
  RUN(test_v1_bytes_unchanged);
  RUN(test_damaged_decoders);
  nbrdf_model_destroy(bundle);
  return testing_finish();
}
