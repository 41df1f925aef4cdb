/* Regression test over the minimised fuzzing corpus of the parameter-map
 * path (tests/texture/param_map_corpus/, made by fuzz/fuzz_param_map): as in
 * the fuzzer, the first byte of a file picks the extension, colour data and
 * remapping, the rest is the image. Every file opens into a map whose texels
 * read finite and >= 0 (or fail naming the file), or is refused naming the
 * file. Under the sanitizer build this replays what the fuzzer explored. */
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

/* 1: opened and read, 0: refused (properly or not, CHECKed). */
static int replay(const unsigned char *data, size_t size, const char *name) {
  char path[1024];
  texture_param_map_options o;
  snprintf(path, sizeof path, "%s/corpus_map.%s", testing_tmpdir(),
           param_map_input_decode(data[0], &o));
  FILE *f = fopen(path, "wb");
  CHECK(f && fwrite(data + 1, 1, size - 1, f) == size - 1);
  if (f) fclose(f);
  texture_param_map *m = NULL;
  nbrdf_error err = {0};
  nbrdf_status st = texture_param_map_open(path, &o, &m, &err);
  int opened = st == NBRDF_OK;
  if (!opened) {
    CHECK_MSG(m == NULL && strstr(err.message, path), "%s: \"%s\"", name, err.message);
  } else {
    const texture_param_map_info *in = texture_param_map_get_info(m);
    CHECK_MSG(in->width >= 1 && in->height >= 1 && (in->channels == 1 || in->channels == 3),
              "%s: %dx%d, %d channels", name, in->width, in->height, in->channels);
    size_t floats = (size_t)in->width * in->channels;
    int rows = in->height < 16 ? in->height : 16;
    if (floats * rows <= (1u << 22)) {
      float *buf = malloc(sizeof(float) * floats * rows);
      st = texture_param_map_read_rows(m, 0, rows, buf, &err);
      if (st != NBRDF_OK)
        CHECK_MSG(strstr(err.message, path), "%s: rows: \"%s\"", name, err.message);
      else
        for (size_t k = 0; k < floats * rows; k++)
          CHECK_MSG(isfinite(buf[k]) && buf[k] >= 0.0f, "%s: value %zu is %g", name, k,
                    (double)buf[k]);
      free(buf);
    }
  }
  texture_param_map_close(m);
  unlink(path);
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
