/* safetensors: write -> read round trips, files laid out byte by byte as PyTorch's
 * safetensors writes them (F32, F16, BF16, F64), look-ups, and the atomic save. */
#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "nn/safetensors.h"
#include "st_fixture.h"
#include "testing.h"

static char *path_in_tmp(const char *name) {
  static char path[512];
  snprintf(path, sizeof path, "%s/%s", testing_tmpdir(), name);
  return path;
}

static unsigned char *read_file(const char *path, size_t *size) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  unsigned char *b = malloc((size_t)n + 1);
  *size = fread(b, 1, (size_t)n, f);
  fclose(f);
  return b;
}

/* Files in a directory other than . and .. */
static int count_entries(const char *dir) {
  DIR *d = opendir(dir);
  if (!d) return -1;
  int n = 0;
  for (struct dirent *e; (e = readdir(d));)
    n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
  closedir(d);
  return n;
}

static int same_bits(const float *a, const float *b, size_t n) { return !memcmp(a, b, 4 * n); }

static void test_round_trip(void) {
  nbrdf_error err_storage = {0}, *err = &err_storage;
  nn_st_writer *w = NULL;
  CHECK_OK(nn_st_writer_create(&w, err), err);
  float fc[6] = {1.5f, -0.0f, 1e-42f /* subnormal */, INFINITY, NAN, 3.0e38f};
  float bias[3] = {0.25f, -1.0f, 7.0f}, scalar = 42.0f;
  int64_t fc_shape[2] = {2, 3}, bias_shape[1] = {3}, empty_shape[2] = {0, 5};
  CHECK_OK(nn_st_writer_add(w, "block0.fc.weight", 2, fc_shape, fc, err), err);
  CHECK_OK(nn_st_writer_add(w, "block0.fc.bias", 1, bias_shape, bias, err), err);
  CHECK_OK(nn_st_writer_add(w, "scale", 0, NULL, &scalar, err), err);
  CHECK_OK(nn_st_writer_add(w, "empty", 2, empty_shape, NULL, err), err);
  CHECK_OK(nn_st_writer_add(w, "caf\xc3\xa9 \"quoted\"\n\\", 1, bias_shape, bias, err), err);
  CHECK_OK(nn_st_writer_set_metadata(w, "width", "128", err), err);
  CHECK_OK(nn_st_writer_set_metadata(w, "arch", "{\"blocks\": 4}", err), err);
  CHECK_OK(nn_st_writer_set_metadata(w, "width", "256", err), err); /* replaces */
  bias[0] = 99.0f; /* the writer copied: the file must hold 0.25 */
  uint64_t saved_sum = 0;
  const char *path = path_in_tmp("rt.safetensors");
  CHECK_OK(nn_st_writer_save(w, path, &saved_sum, err), err);

  nn_st_reader *r = NULL;
  CHECK_OK(nn_st_open(path, &r, err), err);
  if (!r) {
    nn_st_writer_destroy(w);
    return;
  }
  CHECK(nn_st_tensor_count(r) == 5);
  CHECK(nn_st_checksum(r) == saved_sum);
  CHECK(strcmp(nn_st_label(r), path) == 0);
  const nn_st_tensor *t = nn_st_find(r, "block0.fc.weight");
  CHECK(t && t->ndim == 2 && t->shape[0] == 2 && t->shape[1] == 3 && t->count == 6);
  CHECK(t && t->dtype == NBRDF_ST_F32 && same_bits(t->data, fc, 6));
  t = nn_st_find(r, "block0.fc.bias");
  CHECK(t && t->data[0] == 0.25f && t->data[2] == 7.0f);
  t = nn_st_find(r, "scale");
  CHECK(t && t->ndim == 0 && t->count == 1 && t->data[0] == 42.0f);
  t = nn_st_find(r, "empty");
  CHECK(t && t->ndim == 2 && t->shape[0] == 0 && t->count == 0 && t->data == NULL);
  CHECK(nn_st_find(r, "caf\xc3\xa9 \"quoted\"\n\\") != NULL);
  CHECK(nn_st_find(r, "missing") == NULL);
  /* Iteration is in name order. */
  for (size_t i = 1; i < nn_st_tensor_count(r); i++)
    CHECK(strcmp(nn_st_tensor_at(r, i - 1)->name, nn_st_tensor_at(r, i)->name) < 0);
  CHECK(nn_st_tensor_at(r, 5) == NULL);
  CHECK(nn_st_metadata_count(r) == 2);
  CHECK(strcmp(nn_st_metadata_key(r, 0), "arch") == 0);
  CHECK(strcmp(nn_st_metadata_value(r, 0), "{\"blocks\": 4}") == 0);
  CHECK(strcmp(nn_st_metadata_get(r, "width"), "256") == 0);
  CHECK(nn_st_metadata_get(r, "depth") == NULL);
  const char *v = NULL;
  CHECK_OK(nn_st_metadata_require(r, "width", &v, err), err);
  CHECK_FAILS(nn_st_metadata_require(r, "depth", &v, err), NBRDF_ERR_MISMATCH, err,
              "metadata has no key 'depth'");

  /* Re-saving what was read gives the same bytes: the writer is deterministic, whatever
   * the order tensors were added in. */
  nn_st_writer *w2 = NULL;
  CHECK_OK(nn_st_writer_create(&w2, err), err);
  for (size_t i = nn_st_tensor_count(r); i-- > 0;) {
    t = nn_st_tensor_at(r, i);
    CHECK_OK(nn_st_writer_add_borrowed(w2, t->name, t->ndim, t->shape, t->data, err), err);
  }
  for (size_t i = 0; i < nn_st_metadata_count(r); i++)
    CHECK_OK(
        nn_st_writer_set_metadata(w2, nn_st_metadata_key(r, i), nn_st_metadata_value(r, i), err),
        err);
  void *bytes = NULL;
  size_t size = 0, file_size = 0;
  CHECK_OK(nn_st_writer_serialize(w2, &bytes, &size, err), err);
  unsigned char *file = read_file(path, &file_size);
  CHECK(file && size == file_size && memcmp(bytes, file, size) == 0);
  CHECK(nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, bytes, size) == saved_sum);
  /* Header length is a multiple of 8, padded with spaces; data starts 8-aligned. */
  uint64_t n = 0;
  for (int k = 7; k >= 0; k--)
    n = n << 8 | file[k];
  size_t last = 8 + (size_t)n - 1;
  while (file[last] == ' ')
    last--;
  CHECK(n % 8 == 0 && file[8] == '{' && file[last] == '}' && 8 + (size_t)n - 1 - last < 8);
  free(bytes);
  free(file);
  nn_st_writer_destroy(w2);
  nn_st_close(r); /* w2 borrowed r's floats: destroyed first */
  nn_st_writer_destroy(w);
}

/* Exactly the bytes Python's safetensors writes for
 * save_file({"w": torch.tensor([1.0, -2.0])}, metadata={"format": "pt"}). */
static void test_writer_bytes_match_reference_layout(void) {
  const char *json = "{\"__metadata__\":{\"format\":\"pt\"},"
                     "\"w\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[0,8]}}";
  const unsigned char data[8] = {0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0xc0};
  size_t expected_size = 0;
  unsigned char *expected = st_build_raw(json, 0, data, 8, &expected_size);
  nbrdf_error err_storage = {0}, *err = &err_storage;
  nn_st_writer *w = NULL;
  CHECK_OK(nn_st_writer_create(&w, err), err);
  const float values[2] = {1.0f, -2.0f};
  const int64_t shape[1] = {2};
  CHECK_OK(nn_st_writer_add(w, "w", 1, shape, values, err), err);
  CHECK_OK(nn_st_writer_set_metadata(w, "format", "pt", err), err);
  void *bytes = NULL;
  size_t size = 0;
  CHECK_OK(nn_st_writer_serialize(w, &bytes, &size, err), err);
  CHECK(size == expected_size && memcmp(bytes, expected, size) == 0);
  /* An empty writer gives "{}" padded to 8. */
  nn_st_writer *empty = NULL;
  CHECK_OK(nn_st_writer_create(&empty, err), err);
  free(bytes);
  CHECK_OK(nn_st_writer_serialize(empty, &bytes, &size, err), err);
  CHECK(size == 16 && memcmp((char *)bytes + 8, "{}      ", 8) == 0);
  free(bytes);
  free(expected);
  nn_st_writer_destroy(empty);
  nn_st_writer_destroy(w);
}

/* A file as PyTorch exports mixed precisions: the reference orders tensors by alignment
 * (F64 first), then name; a pretty-printed header with escapes; F16 and BF16 specials. */
static void test_reads_pytorch_dtypes(void) {
  const char *json =
      "{\n  \"__metadata__\": {\"format\": \"pt\", \"note\": \"\\u00e9\\ud83d\\ude00\\t\"},\n"
      "  \"d\": {\"dtype\": \"F64\", \"shape\": [2], \"data_offsets\": [0, 16]},\n"
      "  \"b\": {\"dtype\": \"BF16\", \"shape\": [3], \"data_offsets\": [16, 22]},\n"
      "  \"h\": {\"dtype\": \"F16\", \"shape\": [2, 3], \"data_offsets\": [22, 34]}\n}";
  const unsigned char data[34] = {
      /* F64: 1.0, -0.1 */
      0, 0, 0, 0, 0, 0, 0xf0, 0x3f, 0x9a, 0x99, 0x99, 0x99, 0x99, 0x99, 0xb9, 0xbf,
      /* BF16: 1.0 (0x3f80), -2.5 (0xc020), 3.140625 (0x4049) */
      0x80, 0x3f, 0x20, 0xc0, 0x49, 0x40,
      /* F16: 1.0, -2.0, 0.5, 65504 (max), 2^-24 (smallest subnormal), -inf */
      0x00, 0x3c, 0x00, 0xc0, 0x00, 0x38, 0xff, 0x7b, 0x01, 0x00, 0x00, 0xfc};
  size_t size = 0;
  unsigned char *file = st_build_raw(json, 0, data, sizeof data, &size);
  nbrdf_error err_storage = {0}, *err = &err_storage;
  nn_st_reader *r = NULL;
  CHECK_OK(nn_st_open_memory(file, size, "torch.safetensors", &r, err), err);
  free(file);
  if (!r) return;
  const nn_st_tensor *d = nn_st_find(r, "d"), *b = nn_st_find(r, "b"), *h = nn_st_find(r, "h");
  CHECK(d && d->dtype == NBRDF_ST_F64 && d->data[0] == 1.0f && d->data[1] == (float)-0.1);
  CHECK(b && b->dtype == NBRDF_ST_BF16 && b->data[0] == 1.0f && b->data[1] == -2.5f &&
        b->data[2] == 3.140625f);
  CHECK(h && h->dtype == NBRDF_ST_F16 && h->ndim == 2 && h->shape[1] == 3);
  if (h) {
    const float want[6] = {1.0f, -2.0f, 0.5f, 65504.0f, 0x1p-24f, -INFINITY};
    CHECK(same_bits(h->data, want, 6));
  }
  CHECK(strcmp(nn_st_metadata_get(r, "note"), "\xc3\xa9\xf0\x9f\x98\x80\t") == 0);
  CHECK(strcmp(nn_st_dtype_name(NBRDF_ST_BF16), "BF16") == 0);
  /* nn_st_expect refuses the non-finite value. */
  const int64_t shape[2] = {2, 3};
  CHECK_FAILS(nn_st_expect(r, "h", 2, shape, NULL, err), NBRDF_ERR_FORMAT, err,
              "torch.safetensors: tensor 'h' holds an infinity at flat index 5");
  nn_st_close(r);

  /* F64 beyond float's range becomes an infinity, not undefined behaviour. */
  const unsigned char big[8] = {0, 0, 0, 0, 0, 0, 0xf0, 0x7f - 0x10}; /* 2^768 */
  file = st_build_raw("{\"x\":{\"dtype\":\"F64\",\"shape\":[],\"data_offsets\":[0,8]},"
                      "\"__metadata__\":null}",
                      0, big, 8, &size);
  CHECK_OK(nn_st_open_memory(file, size, "big", &r, err), err);
  CHECK(r && isinf(nn_st_find(r, "x")->data[0]) && nn_st_metadata_count(r) == 0);
  nn_st_close(r);
  free(file);
}

static void test_expect(void) {
  nbrdf_error err_storage = {0}, *err = &err_storage;
  nn_st_writer *w = NULL;
  CHECK_OK(nn_st_writer_create(&w, err), err);
  float m[6] = {1, 2, 3, 4, 5, 6};
  const int64_t s23[2] = {2, 3}, s32[2] = {3, 2}, s6[1] = {6};
  CHECK_OK(nn_st_writer_add(w, "block3.fc1.weight", 2, s23, m, err), err);
  void *bytes = NULL;
  size_t size = 0;
  CHECK_OK(nn_st_writer_serialize(w, &bytes, &size, err), err);
  nn_st_reader *r = NULL;
  CHECK_OK(nn_st_open_memory(bytes, size, "decoder.safetensors", &r, err), err);
  free(bytes);
  nn_st_writer_destroy(w);
  if (!r) return;
  const float *data = NULL;
  CHECK_OK(nn_st_expect(r, "block3.fc1.weight", 2, s23, &data, err), err);
  CHECK(data && data[5] == 6.0f);
  CHECK_FAILS(nn_st_expect(r, "block3.fc1.weight", 2, s32, &data, err), NBRDF_ERR_MISMATCH, err,
              "decoder.safetensors: tensor 'block3.fc1.weight' has shape [2, 3], "
              "expected [3, 2]");
  CHECK_FAILS(nn_st_expect(r, "block3.fc1.weight", 1, s6, &data, err), NBRDF_ERR_MISMATCH, err,
              "has shape [2, 3], expected [6]");
  CHECK_FAILS(nn_st_expect(r, "block3.fc2.weight", 2, s23, &data, err), NBRDF_ERR_MISMATCH, err,
              "decoder.safetensors: has no tensor 'block3.fc2.weight'");
  float copy[6] = {0};
  CHECK_OK(nn_st_expect_copy(r, "block3.fc1.weight", 2, s23, copy, err), err);
  CHECK(same_bits(copy, m, 6));
  nn_st_close(r);
}

static void test_writer_refuses_bad_tensors(void) {
  nbrdf_error err_storage = {0}, *err = &err_storage;
  nn_st_writer *w = NULL;
  CHECK_OK(nn_st_writer_create(&w, err), err);
  float x[2] = {1, 2};
  const int64_t s2[1] = {2}, neg[1] = {-2}, s9[9] = {1, 1, 1, 1, 1, 1, 1, 1, 2};
  CHECK_OK(nn_st_writer_add(w, "x", 1, s2, x, err), err);
  CHECK_FAILS(nn_st_writer_add(w, "x", 1, s2, x, err), NBRDF_ERR_ARGUMENT, err,
              "tensor 'x' was already added");
  CHECK_FAILS(nn_st_writer_add(w, "", 1, s2, x, err), NBRDF_ERR_ARGUMENT, err,
              "cannot name a tensor");
  CHECK_FAILS(nn_st_writer_add(w, "__metadata__", 1, s2, x, err), NBRDF_ERR_ARGUMENT, err,
              "cannot name a tensor");
  CHECK_FAILS(nn_st_writer_add(w, "y", 1, neg, x, err), NBRDF_ERR_ARGUMENT, err,
              "dimension 0 is negative");
  CHECK_FAILS(nn_st_writer_add(w, "y", 9, s9, x, err), NBRDF_ERR_ARGUMENT, err,
              "ndim 9 is outside [0, 8]");
  CHECK_FAILS(nn_st_writer_add(w, "y", 1, s2, NULL, err), NBRDF_ERR_ARGUMENT, err, "data is NULL");
  CHECK_FAILS(nn_st_writer_add(w, "\xff", 1, s2, x, err), NBRDF_ERR_ARGUMENT, err,
              "not valid UTF-8");
  CHECK_FAILS(nn_st_writer_set_metadata(w, "k", "\xc3", err), NBRDF_ERR_ARGUMENT, err,
              "metadata value");
  nn_st_writer_destroy(w);
}

static void test_borrowed_data_is_read_at_save(void) {
  nbrdf_error err_storage = {0}, *err = &err_storage;
  nn_st_writer *w = NULL;
  CHECK_OK(nn_st_writer_create(&w, err), err);
  float x[2] = {1, 2};
  const int64_t s2[1] = {2};
  CHECK_OK(nn_st_writer_add_borrowed(w, "x", 1, s2, x, err), err);
  x[1] = 5.0f;
  void *bytes = NULL;
  size_t size = 0;
  CHECK_OK(nn_st_writer_serialize(w, &bytes, &size, err), err);
  nn_st_reader *r = NULL;
  CHECK_OK(nn_st_open_memory(bytes, size, "b", &r, err), err);
  CHECK(r && nn_st_find(r, "x")->data[1] == 5.0f);
  nn_st_close(r);
  free(bytes);
  nn_st_writer_destroy(w);
}

static void test_save_failures_leave_nothing(void) {
  nbrdf_error err_storage = {0}, *err = &err_storage;
  nn_st_writer *w = NULL;
  CHECK_OK(nn_st_writer_create(&w, err), err);
  static float big[4096];
  const int64_t shape[1] = {4096};
  CHECK_OK(nn_st_writer_add(w, "x", 1, shape, big, err), err);

  /* A directory that does not exist. */
  char path[600];
  snprintf(path, sizeof path, "%s/no/such/dir/w.safetensors", testing_tmpdir());
  CHECK_FAILS(nn_st_writer_save(w, path, NULL, err), NBRDF_ERR_IO, err, "cannot create a file in");
  CHECK(strstr(err->message, path) == err->message);

  /* The target is a directory: refused before anything is written. */
  char dir[256];
  snprintf(dir, sizeof dir, "%s/fail", testing_tmpdir());
  CHECK(mkdir(dir, 0777) == 0);
  snprintf(path, sizeof path, "%s/target", dir);
  CHECK(mkdir(path, 0777) == 0);
  CHECK_FAILS(nn_st_writer_save(w, path, NULL, err), NBRDF_ERR_ARGUMENT, err, "is a directory");
  CHECK(count_entries(dir) == 1);

  /* A write that fails half-way (file size limit; works as root too): the existing file is
   * untouched and no temporary file is left. */
  snprintf(path, sizeof path, "%s/keep.safetensors", dir);
  FILE *f = fopen(path, "wb");
  fputs("old", f);
  fclose(f);
  struct rlimit old_limit, limit;
  getrlimit(RLIMIT_FSIZE, &old_limit);
  limit = old_limit;
  limit.rlim_cur = 1000;
  void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
  CHECK(setrlimit(RLIMIT_FSIZE, &limit) == 0);
  CHECK_FAILS(nn_st_writer_save(w, path, NULL, err), NBRDF_ERR_IO, err, "write failed");
  setrlimit(RLIMIT_FSIZE, &old_limit);
  signal(SIGXFSZ, old_handler);
  size_t size = 0;
  unsigned char *kept = read_file(path, &size);
  CHECK(kept && size == 3 && memcmp(kept, "old", 3) == 0);
  free(kept);
  CHECK(count_entries(dir) == 2);

  /* A read-only directory (meaningless as root, who may write anywhere). */
  if (geteuid() != 0) {
    char ro[256];
    snprintf(ro, sizeof ro, "%s/ro", testing_tmpdir());
    CHECK(mkdir(ro, 0555) == 0);
    snprintf(path, sizeof path, "%s/w.safetensors", ro);
    CHECK_FAILS(nn_st_writer_save(w, path, NULL, err), NBRDF_ERR_IO, err, "Permission denied");
    CHECK(count_entries(ro) == 0);
  }

  /* Saving over the file a reader was opened from is safe: the reader holds no reference,
   * and a new reader sees the new content. */
  snprintf(path, sizeof path, "%s/same.safetensors", dir);
  CHECK_OK(nn_st_writer_save(w, path, NULL, err), err);
  nn_st_reader *r = NULL, *r2 = NULL;
  CHECK_OK(nn_st_open(path, &r, err), err);
  nn_st_writer *w2 = NULL;
  const float seven = 7.0f;
  CHECK_OK(nn_st_writer_create(&w2, err), err);
  CHECK_OK(nn_st_writer_add(w2, "x", 0, NULL, &seven, err), err);
  CHECK_OK(nn_st_writer_save(w2, path, NULL, err), err);
  CHECK_OK(nn_st_open(path, &r2, err), err);
  CHECK(r && nn_st_find(r, "x")->count == 4096 && nn_st_find(r, "x")->data[0] == 0.0f);
  CHECK(r2 && nn_st_find(r2, "x")->count == 1 && nn_st_find(r2, "x")->data[0] == 7.0f);
  CHECK(r && r2 && nn_st_checksum(r) != nn_st_checksum(r2));
  nn_st_close(r);
  nn_st_close(r2);
  CHECK(count_entries(dir) == 3);
  nn_st_writer_destroy(w2);
  nn_st_writer_destroy(w);

  CHECK_FAILS(nn_st_open(dir, &r, err), NBRDF_ERR_IO, err, "is a directory, not a file");
  snprintf(path, sizeof path, "%s/absent.safetensors", dir);
  CHECK_FAILS(nn_st_open(path, &r, err), NBRDF_ERR_IO, err, "cannot open: No such file");
}

int main(void) {
  RUN(test_round_trip);
  RUN(test_writer_bytes_match_reference_layout);
  RUN(test_reads_pytorch_dtypes);
  RUN(test_expect);
  RUN(test_writer_refuses_bad_tensors);
  RUN(test_borrowed_data_is_read_at_save);
  RUN(test_save_failures_leave_nothing);
  return testing_finish();
}
