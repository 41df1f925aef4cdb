/* Regression test over the minimised fuzzing corpus of the parameter-map
 * path (tests/texture/param_map_corpus/, made by fuzz/fuzz_param_map): as in
 * the fuzzer, the first byte of a file picks the extension, colour data and
 * remapping, the rest is the image. Every file opens into a map whose texels
 * read finite and >= 0 (or fail naming the file), or is refused naming the
 * file. Each input is read both as a file and from memory (the fuzzer's way).
 * Under the sanitizer build this replays what the fuzzer explored. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../../fuzz/param_map_input.h"
#include "testing.h"
#include "texture/param_map.h"

static unsigned char *slurp(const char *path, size_t *size) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  unsigned char *buf = malloc(1 << 16);
  *size = buf ? fread(buf, 1, 1 << 16, f) : 0;
  fclose(f);
  return buf;
}

/* Opens the input as a file (as `nbrdf bake` does) or from memory (as the fuzzer does).
 * Returns the map or NULL (refused, CHECKed to name the input). */
static texture_param_map *open_input(const unsigned char *data, size_t size, const char *name,
                                     int memory, char *label, size_t label_size) {
  texture_param_map_options o;
  const char *ext = param_map_input_decode(data[0], &o);
  texture_param_map *m = NULL;
  nbrdf_error err = {0};
  nbrdf_status st;
  if (memory) {
    snprintf(label, label_size, "corpus_map.%s", ext);
    st = texture_param_map_open_memory(label, param_map_input_format(data[0]), data + 1,
                                       size - 1, &o, &m, &err);
  } else {
    snprintf(label, label_size, "%s/corpus_map.%s", testing_tmpdir(), ext);
    FILE *f = fopen(label, "wb");
    CHECK(f && fwrite(data + 1, 1, size - 1, f) == size - 1);
    if (f) fclose(f);
    st = texture_param_map_open(label, &o, &m, &err);
  }
  if (st != NBRDF_OK)
    CHECK_MSG(m == NULL && strstr(err.message, label), "%s: \"%s\"", name, err.message);
  return st == NBRDF_OK ? m : NULL;
}

/* The first rows of an opened map (malloc'd; NULL when too large or refused, CHECKed). */
static float *read_first_rows(texture_param_map *m, const char *label, const char *name,
                              size_t *count) {
  const texture_param_map_info *in = texture_param_map_get_info(m);
  CHECK_MSG(in->width >= 1 && in->height >= 1 && (in->channels == 1 || in->channels == 3),
            "%s: %dx%d, %d channels", name, in->width, in->height, in->channels);
  size_t floats = (size_t)in->width * in->channels;
  int rows = in->height < 16 ? in->height : 16;
  *count = 0;
  if (floats * rows > (1u << 22)) return NULL;
  float *buf = malloc(sizeof(float) * floats * rows);
  nbrdf_error err = {0};
  if (texture_param_map_read_rows(m, 0, rows, buf, &err) != NBRDF_OK) {
    CHECK_MSG(strstr(err.message, label), "%s: rows: \"%s\"", name, err.message);
    free(buf);
    return NULL;
  }
  for (size_t k = 0; k < floats * rows; k++)
    CHECK_MSG(isfinite(buf[k]) && buf[k] >= 0.0f, "%s: value %zu is %g", name, k, (double)buf[k]);
  *count = floats * rows;
  return buf;
}

/* 1: opened as a file, 0: refused. An input the in-memory reader accepts must open as a
 * file too, with the same size and texels (the same decoder over the same bytes); the
 * converse need not hold: by name, OpenImageIO tries other formats after the extension's. */
static int replay(const unsigned char *data, size_t size, const char *name) {
  char file_label[1024], mem_label[64];
  texture_param_map *f = open_input(data, size, name, 0, file_label, sizeof file_label);
  texture_param_map *m = open_input(data, size, name, 1, mem_label, sizeof mem_label);
  size_t nf = 0, nm = 0;
  float *vf = f ? read_first_rows(f, file_label, name, &nf) : NULL;
  float *vm = m ? read_first_rows(m, mem_label, name, &nm) : NULL;
  if (m) {
    CHECK_MSG(f != NULL, "%s: opens from memory but not as a file", name);
    if (f) {
      const texture_param_map_info *a = texture_param_map_get_info(f);
      const texture_param_map_info *b = texture_param_map_get_info(m);
      CHECK_MSG(a->width == b->width && a->height == b->height && a->channels == b->channels,
                "%s: %dx%dx%d as a file, %dx%dx%d from memory", name, a->width, a->height,
                a->channels, b->width, b->height, b->channels);
      CHECK_MSG(nf == nm && (!nf || !memcmp(vf, vm, nf * sizeof(float))),
                "%s: texels differ between file and memory (%zu vs %zu)", name, nf, nm);
    }
  }
  free(vf);
  free(vm);
  int opened = f != NULL;
  texture_param_map_close(f);
  texture_param_map_close(m);
  unlink(file_label);
  return opened;
}

static void test_corpus(void) {
  char dir[512];
  snprintf(dir, sizeof dir, "%s/tests/texture/param_map_corpus", testing_source_dir());
  size_t n = 0;
  char **names = testing_list_dir(dir, &n); /* sorted: a stable order for the log */
  if (!names) return;
  int opened = 0, refused = 0;
  for (size_t i = 0; i < n; i++) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    size_t size = 0;
    unsigned char *data = slurp(path, &size);
    if (data && size >= 1) {
      if (replay(data, size, names[i]))
        opened++;
      else
        refused++;
    }
    free(data);
    free(names[i]);
  }
  free(names);
  printf("corpus: %zu files, %d opened, %d refused\n", n, opened, refused);
  CHECK(n >= 10);
  CHECK(opened > 0 && refused > 0);
}

int main(void) {
  RUN(test_corpus);
  return testing_finish();
}
