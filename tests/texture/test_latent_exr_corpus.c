/* Regression test over the minimised fuzzing corpus of the latent texture
 * reader (tests/texture/latent_exr_corpus/, made by fuzz/fuzz_latent_exr):
 * every file either opens into a self-consistent reader whose tiles read or
 * fail with a message naming the file, or is refused with such a message.
 * Under the sanitizer build this catches any out-of-bounds access or leak the
 * fuzzer once found. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testing.h"
#include "texture/latent_exr.h"
#include "texture/mip_chain.h"

static int refused_properly(nbrdf_status st, const nbrdf_error *err, const char *path) {
  return (st == NBRDF_ERR_FORMAT || st == NBRDF_ERR_IO || st == NBRDF_ERR_UNSUPPORTED) &&
         strstr(err->message, path) && strlen(err->message) > strlen(path) + 10;
}

/* Returns the number of tiles that failed to read. */
static int check_loaded(texture_latent_reader *r, const char *path, const char *name) {
  const texture_latent_info *in = texture_latent_reader_info(r);
  CHECK_MSG(in->width >= 1 && in->height >= 1 && in->levels >= 1, "%s: size", name);
  CHECK_MSG(in->levels == 1 || in->levels == texture_mip_level_count(in->width, in->height),
            "%s: %d levels", name, in->levels);
  CHECK_MSG(in->channels == texture_latent_channel_count(&in->layout), "%s: channels", name);
  size_t tile = (size_t)in->tile_width * in->tile_height * in->channels;
  if (tile > (4u << 20)) return 0;
  float *buf = malloc(tile * sizeof(float));
  int failed = 0, budget = 64;
  for (int level = 0; level < in->levels && budget > 0; level++) {
    int w, h;
    nbrdf_error err = {0};
    CHECK_OK(texture_latent_reader_level_size(r, level, &w, &h, &err), &err);
    for (int y = 0; y < h && budget > 0; y += in->tile_height)
      for (int x = 0; x < w && budget > 0; x += in->tile_width, budget--) {
        int rw = w - x < in->tile_width ? w - x : in->tile_width;
        int rh = h - y < in->tile_height ? h - y : in->tile_height;
        nbrdf_status st = texture_latent_reader_read(r, level, x, y, rw, rh, buf, &err);
        if (st == NBRDF_OK) continue;
        failed++;
        CHECK_MSG(refused_properly(st, &err, path), "%s: tile read: %s \"%s\"", name,
                  nbrdf_status_name(st), err.message);
      }
  }
  free(buf);
  return failed;
}

static void test_corpus(void) {
  char dir[512];
  snprintf(dir, sizeof dir, "%s/tests/texture/latent_exr_corpus", testing_source_dir());
  size_t n = 0;
  char **names = testing_list_dir(dir, &n); /* sorted: a stable order for the log */
  if (!names) return;
  int loaded = 0, refused = 0, bad_tiles = 0;
  for (size_t i = 0; i < n; i++) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    nbrdf_error err = {0};
    texture_latent_reader *r = NULL;
    nbrdf_status st = texture_latent_reader_open(&r, path, &err);
    if (st == NBRDF_OK) {
      loaded++;
      bad_tiles += check_loaded(r, path, names[i]);
    } else {
      refused++;
      CHECK_MSG(r == NULL, "%s: reader returned with a failure", names[i]);
      CHECK_MSG(refused_properly(st, &err, path), "%s: %s \"%s\"", names[i], nbrdf_status_name(st),
                err.message);
    }
    texture_latent_reader_close(r);
    free(names[i]);
  }
  free(names);
  printf("corpus: %zu files, %d opened (%d tiles refused), %d refused\n", n, loaded, bad_tiles,
         refused);
  CHECK(n >= 10);
  CHECK(loaded > 0 && refused > 0);
}

int main(void) {
  RUN(test_corpus);
  return testing_finish();
}
