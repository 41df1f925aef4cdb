/* libFuzzer target for the parameter-map path: what `nbrdf bake --alpha1 FILE`
 * (and every other map option) goes through: texture_param_map_open and
 * texture_param_map_read_rows (src/texture/param_map.c) over the OpenImageIO
 * shim (src/texture/oiio_shim.cpp) and, for colour maps, the OpenColorIO one.
 * OpenImageIO and the codecs under it are the system's and not instrumented:
 * the coverage that guides the fuzzer is nbrdf's own.
 *
 * The first byte of an input chooses the format (the reader OpenImageIO
 * uses, by name, with no probing of others), whether the map is colour data
 * (sRGB -> linear) and whether integer samples are remapped; the rest is the
 * file's bytes, read from memory (texture_param_map_open_memory: OIIO's
 * IOMemReader, and the structure walk over the same bytes), so an execution
 * costs no file system calls. The corpus replay (tests/texture/
 * test_param_map_corpus.c) reads each input both from memory and as a file, as
 * `nbrdf bake` does, and checks the two agree.
 *
 * Properties checked on every input, beyond "no crash, no sanitizer report":
 * - a refusal returns no map and a message that names the file;
 * - an accepted map has a size >= 1 and 1 or 3 channels delivered;
 * - bands of rows (as a bake reads them, up to a budget) read, or fail the
 *   same way; every texel delivered is finite and >= 0 (the map's promise).
 *
 * Build and run: see fuzz/README.md. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "param_map_input.h"
#include "texture/param_map.h"

#define REQUIRE(cond)                                                                              \
  do {                                                                                             \
    if (!(cond)) abort();                                                                          \
  } while (0)

/* Texels read per input at most, and floats of one band at most: a forged
 * header can claim a 2^31-wide image. */
#define TEXEL_BUDGET (1u << 18)
#define BAND_FLOATS_MAX (1u << 22)
/* As a bake: a band holds about this many texels (src/bake/bake.c). */
#define BAND_TEXELS 65536

static void check_refusal(nbrdf_status st, const nbrdf_error *err, const char *path) {
  REQUIRE(st != NBRDF_OK);
  REQUIRE(strstr(err->message, path) != NULL);
}

static void read_map(texture_param_map *m, const char *path) {
  const texture_param_map_info *in = texture_param_map_get_info(m);
  REQUIRE(in->width >= 1 && in->height >= 1);
  REQUIRE(in->channels == 1 || in->channels == 3);
  REQUIRE(in->file_channels >= in->channels && in->file_channels <= 4);
  int rows = BAND_TEXELS / in->width;
  if (rows < 1) rows = 1;
  if (rows > in->height) rows = in->height;
  size_t floats = (size_t)rows * (size_t)in->width * (size_t)in->channels;
  if (floats > BAND_FLOATS_MAX) return;
  float *buf = malloc(floats * sizeof(float));
  REQUIRE(buf != NULL);
  size_t budget = TEXEL_BUDGET;
  for (int y = 0; y < in->height && budget > 0; y += rows) {
    int n = in->height - y < rows ? in->height - y : rows;
    nbrdf_error err = {0};
    nbrdf_status st = texture_param_map_read_rows(m, y, n, buf, &err);
    size_t texels = (size_t)n * (size_t)in->width;
    budget = texels < budget ? budget - texels : 0;
    if (st != NBRDF_OK) {
      check_refusal(st, &err, path);
      break; /* a bake stops at the first error */
    }
    for (size_t k = 0; k < texels * (size_t)in->channels; k++)
      REQUIRE(isfinite(buf[k]) && buf[k] >= 0.0f);
  }
  free(buf);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 1) return 0;
  texture_param_map_options o;
  const char *ext = param_map_input_decode(data[0], &o);
  char label[64];
  snprintf(label, sizeof label, "fuzz_param_map.%s", ext);
  texture_param_map *m = NULL;
  nbrdf_error err = {0};
  nbrdf_status st = texture_param_map_open_memory(label, param_map_input_format(data[0]),
                                                  data + 1, size - 1, &o, &m, &err);
  if (st == NBRDF_OK) {
    REQUIRE(m != NULL);
    read_map(m, label);
  } else {
    REQUIRE(m == NULL);
    check_refusal(st, &err, label);
  }
  texture_param_map_close(m);
  return 0;
}
