/* The bad-map corpus (tests/texture/bad_maps/, made by its make.sh) and
 * special files given as maps: every one is refused with a message naming
 * the file and saying what is wrong, in the normal and the sanitizer builds;
 * and alpha is ignored: colour under alpha = 0 reads as stored. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "testing.h"
#include "texture/param_map.h"

static void corpus_path(char *buf, size_t cap, const char *name) {
  snprintf(buf, cap, "%s/tests/texture/bad_maps/%s", testing_source_dir(), name);
}

/* Opens and reads every row; returns the status, the error in *err. */
static nbrdf_status open_and_read(const char *path, texture_param_kind kind, nbrdf_error *err) {
  texture_param_map_options o = NBRDF_PARAM_MAP_OPTIONS_DEFAULT;
  o.kind = kind;
  texture_param_map *m = NULL;
  nbrdf_status st = texture_param_map_open(path, &o, &m, err);
  if (st != NBRDF_OK) {
    CHECK_MSG(m == NULL, "%s: a map returned with a failure", path);
    return st;
  }
  const texture_param_map_info *in = texture_param_map_get_info(m);
  float *rows = malloc(sizeof(float) * (size_t)in->width * in->height * in->channels);
  st = texture_param_map_read_rows(m, 0, in->height, rows, err);
  free(rows);
  texture_param_map_close(m);
  return st;
}

/* The same file through the in-memory reader (what the fuzzer drives). */
static nbrdf_status open_memory(const char *path, nbrdf_error *err) {
  FILE *f = fopen(path, "rb");
  unsigned char *buf = malloc(1 << 16);
  size_t n = f && buf ? fread(buf, 1, 1 << 16, f) : 0;
  if (f) fclose(f);
  const char *dot = strrchr(path, '.');
  texture_param_map *m = NULL;
  nbrdf_status st = texture_param_map_open_memory(
      path, dot && !strcmp(dot, ".png") ? "png" : dot && !strcmp(dot, ".bmp") ? "bmp"
                                                  : dot && !strcmp(dot, ".pgm") ? "pnm" : "openexr",
      buf, n, NULL, &m, err);
  texture_param_map_close(m);
  free(buf);
  return st;
}

static void test_refused(void) {
  static const struct {
    const char *file, *says;
  } cases[] = {
      {"truncated.png", "claims"},
      {"bitflip.png", "cannot read rows"},
      {"chunk_length.png", "PNG chunk 'tEXt' at byte"},
      {"empty.png", "is empty"},
      {"text.png", "Not a PNG file"},
      {"truncated.exr", "claims"},
      {"attr_length.exr", "OpenEXR attribute 'channels' claims"},
      {"damaged_chunk.exr", "damaged scanline chunk at row 0"},
      {"huge.bmp", "BMP texels at byte 0 overlap its headers or lie past the end"},
      {"huge.pgm", "2222224x3 texels; a map is at most 1048576 a side"},
      {"dense.pgm", "a pnm image of 60000x60000 texels cannot come from 22 bytes"},
      {"rle8_24bit.bmp", "BMP of 24 bits per texel with compression 1 (not a valid pair)"},
      {"box2i_size.exr", "attribute 'dataWindow' of type box2i declares 7 bytes, expected 16"},
      {"two_channels.exr", "2 channels"},
      {"five_channels.exr", "5 channels"},
      {"nan.exr", "texel (1, 1) is NaN"},
      {"inf.exr", "texel (1, 1) is infinite"},
      {"negative.exr", "texel (1, 1) is negative"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    char path[1024];
    corpus_path(path, sizeof path, cases[i].file);
    for (int kind = 0; kind < 2; kind++) {
      nbrdf_error err = {0};
      nbrdf_status st = open_and_read(path, (texture_param_kind)kind, &err);
      CHECK_MSG(st != NBRDF_OK, "%s was accepted", cases[i].file);
      CHECK_MSG(strstr(err.message, path) && strstr(err.message, cases[i].says),
                "%s: \"%s\" lacks the path or \"%s\"", cases[i].file, err.message, cases[i].says);
    }
    /* Refused from memory too where the header is at fault (texels are checked on read). */
    if (!strstr(cases[i].says, "texel") && !strstr(cases[i].says, "rows")) {
      nbrdf_error err = {0};
      CHECK_MSG(open_memory(path, &err) != NBRDF_OK, "%s accepted from memory", cases[i].file);
    }
  }
}

/* Special files: refused at once (a FIFO would block the open, /dev/zero
 * never end), saying what they are. */
static void test_special_files(void) {
  char dir[1024], fifo[1024];
  snprintf(dir, sizeof dir, "%s/map_dir.png", testing_tmpdir());
  snprintf(fifo, sizeof fifo, "%s/map_fifo.png", testing_tmpdir());
  CHECK(mkdir(dir, 0755) == 0);
  CHECK(mkfifo(fifo, 0644) == 0);
  static const char *const says[] = {"is a directory", "is a FIFO", "is a character device",
                                     "is a character device", "cannot open"};
  const char *paths[] = {dir, fifo, "/dev/zero", "/dev/urandom", "/nonexistent/map.png"};
  for (int i = 0; i < 5; i++) {
    nbrdf_error err = {0};
    nbrdf_status st = open_and_read(paths[i], NBRDF_PARAM_DATA, &err);
    CHECK_MSG(st != NBRDF_OK, "%s accepted", paths[i]);
    CHECK_MSG(strstr(err.message, paths[i]) && strstr(err.message, says[i]),
              "%s: \"%s\" lacks \"%s\"", paths[i], err.message, says[i]);
  }
  rmdir(dir);
  unlink(fifo);
}

static void read_first_row(const char *name, float *out, int *channels) {
  char path[1024];
  corpus_path(path, sizeof path, name);
  texture_param_map *m = NULL;
  nbrdf_error err = {0};
  CHECK_OK(texture_param_map_open(path, NULL, &m, &err), &err);
  if (!m) return;
  const texture_param_map_info *in = texture_param_map_get_info(m);
  *channels = in->channels;
  CHECK(in->width == 2 && in->height == 1);
  CHECK_OK(texture_param_map_read_rows(m, 0, 1, out, &err), &err);
  texture_param_map_close(m);
}

/* OpenImageIO multiplies colour by alpha on read unless asked not to; a
 * parameter map ignores alpha, so both texels read the same. */
static void test_alpha_ignored(void) {
  float v[6] = {0};
  int channels = 0;
  read_first_row("rgba_alpha0.png", v, &channels);
  CHECK(channels == 3);
  const float want[3] = {230 / 255.0f, 128 / 255.0f, 51 / 255.0f};
  for (int c = 0; c < 3; c++) {
    CHECK_NEAR(v[c], want[c], 1e-6);     /* under alpha = 0 */
    CHECK_NEAR(v[3 + c], want[c], 1e-6); /* under alpha = 1 */
  }
  float g[2] = {0};
  read_first_row("grey_alpha0.png", g, &channels);
  CHECK(channels == 1);
  CHECK_NEAR(g[0], 200 / 255.0f, 1e-6);
  CHECK_NEAR(g[1], 200 / 255.0f, 1e-6);
}

int main(void) {
  RUN(test_refused);
  RUN(test_special_files);
  RUN(test_alpha_ignored);
  return testing_finish();
}
