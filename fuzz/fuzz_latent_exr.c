/* libFuzzer target for the latent texture reader (src/texture/latent_exr_read.c,
 * over OpenEXRCore), which `nbrdf verify`, `nbrdf info` and renderers run on
 * files from anywhere.
 *
 * Properties checked on every input, beyond "no crash, no sanitizer report":
 * - a refusal returns no reader, a format/io/unsupported status and a message
 *   that names the file;
 * - an accepted file is self-consistent: sizes >= 1, the level count and
 *   every level's size those of a ROUND_DOWN mip chain, channels matching the
 *   layout, strings non-NULL;
 * - every tile of every level (up to a budget) reads, or fails the same way
 *   as a refusal; values read are readable (ASan sees the whole buffer).
 *
 * The reader takes a path, so each input is written to a per-process file
 * (under $TMPDIR, /tmp by default) first.
 *
 * Build: cmake -S . -B build-fuzz -G Ninja -DCMAKE_C_COMPILER=clang -DNBRDF_BUILD_FUZZ=ON
 *        cmake --build build-fuzz --target fuzz_latent_exr
 * Run:   see fuzz/README.md */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "texture/latent_exr.h"
#include "texture/mip_chain.h"

#define REQUIRE(cond)                                                                              \
  do {                                                                                             \
    if (!(cond)) abort();                                                                          \
  } while (0)

/* Tiles read per input at most: a forged header can claim millions. */
#define TILE_BUDGET 64
/* Bytes of one tile buffer at most (the reader itself allows 256 MiB). */
#define TILE_BYTES_MAX (16u << 20)

static void check_refusal(nbrdf_status st, const nbrdf_error *err, const char *path) {
  REQUIRE(st == NBRDF_ERR_FORMAT || st == NBRDF_ERR_IO || st == NBRDF_ERR_UNSUPPORTED ||
          st == NBRDF_ERR_MEMORY);
  REQUIRE(strstr(err->message, path) != NULL);
}

static void check_reader(texture_latent_reader *r, const char *path) {
  const texture_latent_info *in = texture_latent_reader_info(r);
  REQUIRE(in->width >= 1 && in->height >= 1 && in->levels >= 1);
  REQUIRE(in->levels == 1 || in->levels == texture_mip_level_count(in->width, in->height));
  REQUIRE(in->channels == texture_latent_channel_count(&in->layout));
  REQUIRE(in->tile_width >= 1 && in->tile_height >= 1);
  REQUIRE(in->model_name && in->model_checksum && in->sources && in->settings && in->mip_filter &&
          in->writer);
  size_t tile = (size_t)in->tile_width * (size_t)in->tile_height * (size_t)in->channels;
  if (tile * sizeof(float) > TILE_BYTES_MAX) return;
  float *buf = malloc(tile * sizeof(float));
  REQUIRE(buf != NULL);
  int budget = TILE_BUDGET;
  for (int level = 0; level < in->levels && budget > 0; level++) {
    int w = 0, h = 0;
    nbrdf_error err = {0};
    REQUIRE(texture_latent_reader_level_size(r, level, &w, &h, &err) == NBRDF_OK);
    REQUIRE(w == texture_mip_level_dim(in->width, level));
    REQUIRE(h == texture_mip_level_dim(in->height, level));
    for (int y = 0; y < h && budget > 0; y += in->tile_height)
      for (int x = 0; x < w && budget > 0; x += in->tile_width, budget--) {
        int rw = w - x < in->tile_width ? w - x : in->tile_width;
        int rh = h - y < in->tile_height ? h - y : in->tile_height;
        nbrdf_status st = texture_latent_reader_read(r, level, x, y, rw, rh, buf, &err);
        if (st != NBRDF_OK) {
          check_refusal(st, &err, path);
          continue;
        }
        volatile float sink = 0;
        for (size_t k = 0; k < (size_t)rw * rh * in->channels; k++)
          sink += buf[k];
        (void)sink;
      }
  }
  free(buf);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  static char path[256];
  if (!path[0]) {
    const char *dir = getenv("TMPDIR");
    snprintf(path, sizeof path, "%s/fuzz_latent_exr.%ld.exr", dir && *dir ? dir : "/tmp",
             (long)getpid());
  }
  FILE *f = fopen(path, "wb");
  REQUIRE(f != NULL);
  REQUIRE(fwrite(data, 1, size, f) == size);
  REQUIRE(fclose(f) == 0);
  texture_latent_reader *r = NULL;
  nbrdf_error err = {0};
  nbrdf_status st = texture_latent_reader_open(&r, path, &err);
  if (st == NBRDF_OK) {
    REQUIRE(r != NULL);
    check_reader(r, path);
  } else {
    REQUIRE(r == NULL);
    check_refusal(st, &err, path);
  }
  texture_latent_reader_close(r);
  return 0;
}
