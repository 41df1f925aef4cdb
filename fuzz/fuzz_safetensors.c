/* libFuzzer target for the safetensors reader (src/nn/safetensors_read.c).
 *
 * Properties checked on every input, beyond "no crash, no sanitizer report":
 * - a refusal returns no reader and a message that starts with the label;
 * - an accepted file is self-consistent (count = product of the shape, names sorted,
 *   look-ups find every tensor and metadata key);
 * - writing it back with the writer and reading that gives the same names, shapes,
 *   float bits and metadata (the writer cannot name a tensor "", so such files skip this).
 *
 * Build: cmake -S . -B build-fuzz -G Ninja -DCMAKE_C_COMPILER=clang -DNBRDF_BUILD_FUZZ=ON
 *        cmake --build build-fuzz --target fuzz_safetensors
 * Run:   build-fuzz/fuzz/fuzz_safetensors -dict=fuzz/safetensors.dict CORPUS_DIR SEED_DIR */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "nn/safetensors.h"

#define REQUIRE(cond)                                                                              \
  do {                                                                                             \
    if (!(cond)) abort();                                                                          \
  } while (0)

static void check_consistent(const nn_st_reader *r) {
  size_t n = nn_st_tensor_count(r);
  for (size_t i = 0; i < n; i++) {
    const nn_st_tensor *t = nn_st_tensor_at(r, i);
    REQUIRE(t && t->ndim >= 0 && t->ndim <= NBRDF_ST_MAX_DIMS);
    size_t count = 1;
    for (int d = 0; d < t->ndim; d++)
      count *= (size_t)t->shape[d];
    REQUIRE(count == t->count && (t->data == NULL) == (count == 0));
    volatile float sink = 0;
    for (size_t k = 0; k < t->count; k++)
      sink += t->data[k]; /* every value is readable */
    (void)sink;
    REQUIRE(nn_st_find(r, t->name) == t);
    if (i) REQUIRE(strcmp(nn_st_tensor_at(r, i - 1)->name, t->name) < 0);
    nbrdf_error err = {0};
    nbrdf_status st = nn_st_expect(r, t->name, t->ndim, t->shape, NULL, &err);
    REQUIRE(st == NBRDF_OK || st == NBRDF_ERR_FORMAT); /* FORMAT: a NaN or an infinity */
  }
  for (size_t i = 0; i < nn_st_metadata_count(r); i++)
    REQUIRE(nn_st_metadata_get(r, nn_st_metadata_key(r, i)) == nn_st_metadata_value(r, i));
}

static void check_round_trip(const nn_st_reader *r) {
  size_t n = nn_st_tensor_count(r);
  for (size_t i = 0; i < n; i++)
    if (!nn_st_tensor_at(r, i)->name[0]) return;
  nn_st_writer *w = NULL;
  REQUIRE(nn_st_writer_create(&w, NULL) == NBRDF_OK);
  for (size_t i = 0; i < n; i++) {
    const nn_st_tensor *t = nn_st_tensor_at(r, i);
    REQUIRE(nn_st_writer_add_borrowed(w, t->name, t->ndim, t->shape, t->data, NULL) == NBRDF_OK);
  }
  for (size_t i = 0; i < nn_st_metadata_count(r); i++)
    REQUIRE(nn_st_writer_set_metadata(w, nn_st_metadata_key(r, i), nn_st_metadata_value(r, i),
                                      NULL) == NBRDF_OK);
  void *bytes = NULL;
  size_t size = 0;
  REQUIRE(nn_st_writer_serialize(w, &bytes, &size, NULL) == NBRDF_OK);
  nn_st_reader *back = NULL;
  REQUIRE(nn_st_open_memory(bytes, size, "again", &back, NULL) == NBRDF_OK);
  REQUIRE(nn_st_tensor_count(back) == n);
  for (size_t i = 0; i < n; i++) {
    const nn_st_tensor *a = nn_st_tensor_at(r, i), *b = nn_st_tensor_at(back, i);
    REQUIRE(strcmp(a->name, b->name) == 0 && a->ndim == b->ndim && a->count == b->count);
    REQUIRE(memcmp(a->shape, b->shape, sizeof a->shape) == 0);
    REQUIRE(b->dtype == NBRDF_ST_F32);
    if (a->count) REQUIRE(memcmp(a->data, b->data, a->count * sizeof(float)) == 0);
  }
  REQUIRE(nn_st_metadata_count(back) == nn_st_metadata_count(r));
  for (size_t i = 0; i < nn_st_metadata_count(r); i++) {
    REQUIRE(strcmp(nn_st_metadata_key(r, i), nn_st_metadata_key(back, i)) == 0);
    REQUIRE(strcmp(nn_st_metadata_value(r, i), nn_st_metadata_value(back, i)) == 0);
  }
  nn_st_close(back);
  free(bytes);
  nn_st_writer_destroy(w);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  nbrdf_error err = {0};
  nn_st_reader *r = NULL;
  nbrdf_status st = nn_st_open_memory(data, size, "fuzz", &r, &err);
  if (st != NBRDF_OK) {
    REQUIRE(r == NULL && err.status == st && strncmp(err.message, "fuzz: ", 6) == 0);
    REQUIRE(st == NBRDF_ERR_FORMAT || st == NBRDF_ERR_UNSUPPORTED);
    return 0;
  }
  check_consistent(r);
  check_round_trip(r);
  nn_st_close(r);
  return 0;
}
