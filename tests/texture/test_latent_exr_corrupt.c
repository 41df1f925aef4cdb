/* Damaged latent textures: truncated at many offsets and with bytes flipped
 * all over the file. The reader must fail with a message naming the file, or
 * (for flips inside pixel data that no check can see) succeed; it must never
 * crash, hang or read out of bounds (this test also runs under ASan). */
#include <stdio.h>

#include "latent_fixture.h"

static unsigned char *slurp(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long len = ftell(f);
  fseek(f, 0, SEEK_SET);
  unsigned char *buf = malloc((size_t)len);
  *n = buf ? fread(buf, 1, (size_t)len, f) : 0;
  fclose(f);
  return buf;
}

static void spit(const char *path, const unsigned char *buf, size_t n) {
  FILE *f = fopen(path, "wb");
  if (f) {
    fwrite(buf, 1, n, f);
    fclose(f);
  }
}

/* Opens the file and reads every level whole; returns the status and leaves
 * the message in *err. */
static nbrdf_status read_everything(const char *path, nbrdf_error *err) {
  texture_latent_reader *r = NULL;
  nbrdf_status st = texture_latent_reader_open(&r, path, err);
  if (st != NBRDF_OK) return st;
  const texture_latent_info *in = texture_latent_reader_info(r);
  float *buf = malloc(sizeof(float) * (size_t)in->width * in->height * in->channels);
  for (int l = 0; st == NBRDF_OK && l < in->levels; l++) {
    int w = 0, h = 0;
    st = texture_latent_reader_level_size(r, l, &w, &h, err);
    if (st == NBRDF_OK) st = texture_latent_reader_read(r, l, 0, 0, w, h, buf, err);
  }
  free(buf);
  texture_latent_reader_close(r);
  return st;
}

static void damage(texture_latent_compression comp, texture_latent_storage storage) {
  nbrdf_error e, *err = &e;
  char good[512], bad[512];
  snprintf(good, sizeof good, "%s/good_%d_%d.exr", testing_tmpdir(), (int)comp, (int)storage);
  snprintf(bad, sizeof bad, "%s/bad_%d_%d.exr", testing_tmpdir(), (int)comp, (int)storage);
  texture_latent_layout layout = {3, NBRDF_COLOUR_RGB, 1};
  float *l0 = fixture_texels(37, 29, &layout, 77);
  texture_latent_exr_options opts = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  opts.compression = comp;
  opts.storage = storage;
  opts.tile_size = 16;
  CHECK_OK(fixture_write(good, 37, 29, &layout, NULL, &opts, l0, 29, err), err);
  free(l0);
  CHECK_OK(read_everything(good, err), err);
  size_t n = 0;
  unsigned char *bytes = slurp(good, &n);
  if (!bytes || n < 64) {
    CHECK_MSG(0, "%s: cannot read back", good);
    free(bytes);
    return;
  }

  /* Truncation anywhere loses chunk data (the file ends with the last
   * chunk), so every truncated file must be refused. */
  int refused = 0, tried = 0;
  for (size_t cut = 0; cut < n; cut += cut < 400 ? 7 : n / 97 + 1) {
    spit(bad, bytes, cut);
    nbrdf_status st = read_everything(bad, err);
    tried++;
    refused += st != NBRDF_OK;
    CHECK_MSG(st != NBRDF_OK, "%s truncated to %zu of %zu bytes was accepted", good, cut, n);
    CHECK_MSG(st == NBRDF_OK || strstr(e.message, bad), "message lacks the path: %s", e.message);
  }

  /* Flipped bytes: header, offset table and chunks alike. */
  int flips = 0, detected = 0;
  uint64_t s = 0x9e3779b97f4a7c15ULL ^ (uint64_t)comp;
  for (size_t pos = 0; pos < n; pos += pos < 600 ? 3 : n / 151 + 1) {
    unsigned char saved = bytes[pos];
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    bytes[pos] ^= (unsigned char)(1u + (s >> 56) % 255u);
    spit(bad, bytes, n);
    bytes[pos] = saved;
    nbrdf_status st = read_everything(bad, err);
    flips++;
    detected += st != NBRDF_OK;
    CHECK_MSG(st == NBRDF_OK || (e.message[0] && strstr(e.message, bad)),
              "flip at %zu: status %s, message \"%s\"", pos, nbrdf_status_name(st), e.message);
  }
  printf("  %s %s: %d/%d truncations refused, %d/%d flips detected\n",
         texture_latent_compression_name(comp), texture_latent_storage_name(storage), refused,
         tried, detected, flips);
  free(bytes);
}

static void test_truncated_and_flipped(void) {
  static const texture_latent_compression comps[] = {
      NBRDF_LATENT_PIZ, NBRDF_LATENT_ZIP, NBRDF_LATENT_ZIPS, NBRDF_LATENT_RLE, NBRDF_LATENT_NONE};
  for (int c = 0; c < 5; c++)
    damage(comps[c], c % 2 ? NBRDF_LATENT_FLOAT : NBRDF_LATENT_HALF);
  damage(NBRDF_LATENT_PIZ, NBRDF_LATENT_FLOAT);
}

int main(void) {
  RUN(test_truncated_and_flipped);
  return testing_finish();
}
