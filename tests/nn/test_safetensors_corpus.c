/* Regression test over the minimised fuzzing corpus (tests/nn/safetensors_corpus/, made by
 * fuzz/fuzz_safetensors): every file either loads into a self-consistent reader or is
 * refused with a format/unsupported status and a message naming the file. Under the
 * sanitizer build this catches any out-of-bounds read or leak the fuzzer once found. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nn/safetensors.h"
#include "testing.h"

static void check_loaded(const nn_st_reader *r, const char *path) {
  for (size_t i = 0; i < nn_st_tensor_count(r); i++) {
    const nn_st_tensor *t = nn_st_tensor_at(r, i);
    size_t count = 1;
    for (int d = 0; d < t->ndim; d++)
      count *= (size_t)t->shape[d];
    CHECK_MSG(count == t->count && nn_st_find(r, t->name) == t, "%s: tensor %zu", path, i);
    double sum = 0; /* every value readable */
    for (size_t k = 0; k < t->count; k++)
      sum += t->data[k];
    (void)sum;
  }
  for (size_t i = 0; i < nn_st_metadata_count(r); i++)
    CHECK(nn_st_metadata_get(r, nn_st_metadata_key(r, i)) == nn_st_metadata_value(r, i));
}

static void test_corpus(void) {
  char dir[512];
  snprintf(dir, sizeof dir, "%s/tests/nn/safetensors_corpus", testing_source_dir());
  size_t n = 0;
  char **names = testing_list_dir(dir, &n); /* sorted: a stable order for the log */
  if (!names) return;
  int loaded = 0, refused = 0;
  for (size_t i = 0; i < n; i++) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    nbrdf_error err = {0};
    nn_st_reader *r = NULL;
    nbrdf_status st = nn_st_open(path, &r, &err);
    if (st == NBRDF_OK) {
      loaded++;
      check_loaded(r, names[i]);
    } else {
      refused++;
      CHECK_MSG(r == NULL, "%s: reader returned with a failure", names[i]);
      CHECK_MSG(st == NBRDF_ERR_FORMAT || st == NBRDF_ERR_UNSUPPORTED, "%s: status %s", names[i],
                nbrdf_status_name(st));
      CHECK_MSG(strncmp(err.message, path, strlen(path)) == 0 &&
                    strlen(err.message) > strlen(path) + 10,
                "%s: message \"%s\" does not name the file and the problem", names[i], err.message);
    }
    nn_st_close(r);
    free(names[i]);
  }
  free(names);
  printf("corpus: %zu files, %d loaded, %d refused\n", n, loaded, refused);
  CHECK(n >= 10);
  CHECK(loaded > 0 && refused > 0);
}

int main(void) {
  RUN(test_corpus);
  return testing_finish();
}
