/* Reading safetensors: the layout checks of the format (after the header is parsed by
 * safetensors_header.c), conversion to float, and the look-ups. */
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "core/input_file.h"
#include "nn/safetensors_internal.h"

struct nn_st_reader {
  char *label;
  uint64_t checksum;
  nn_st_header header;      /* entries sorted by name, metadata by key; owns the strings */
  nn_st_tensor *tensors;    /* parallel to header.entries */
  float *values;            /* every tensor's converted data, one block */
};

typedef unsigned long long ull; /* for printf: uint64_t is not long long everywhere */

static int compare_entry_names(const void *a, const void *b) {
  return strcmp(((const nn_st_entry *)a)->name, ((const nn_st_entry *)b)->name);
}

static int compare_meta_keys(const void *a, const void *b) {
  return strcmp(((const nn_st_meta *)a)->key, ((const nn_st_meta *)b)->key);
}

static int compare_entry_offsets(const void *a, const void *b) {
  const nn_st_entry *x = *(const nn_st_entry *const *)a, *y = *(const nn_st_entry *const *)b;
  if (x->begin != y->begin) return x->begin < y->begin ? -1 : 1;
  if (x->end != y->end) return x->end < y->end ? -1 : 1;
  return 0;
}

/* The dtype, shape and offsets of one tensor, on their own and against the data size. */
static nbrdf_status check_entry(const nn_st_entry *e, uint64_t data_size, nn_st_dtype *dtype,
                                uint64_t *count, nbrdf_error *err) {
  size_t elem = 0;
  int known = nn_st_dtype_lookup(e->dtype, dtype, &elem);
  if (known < 0)
    return core_fail(err, NBRDF_ERR_FORMAT, "tensor '%s' has unknown dtype \"%.40s\"", e->name,
                     e->dtype);
  if (known == 0)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED,
                     "tensor '%s' has dtype %s; nbrdf reads only F32, F16, BF16 and F64", e->name,
                     e->dtype);
  char shape[160];
  nn_st_format_shape(shape, sizeof shape, e->ndim, e->shape);
  uint64_t n = 1, bytes = 0;
  for (int d = 0; d < e->ndim; d++) {
    if (e->shape[d] > (uint64_t)INT64_MAX)
      return core_fail(err, NBRDF_ERR_FORMAT, "tensor '%s' has dimension %d of %llu, too large",
                       e->name, d, (ull)e->shape[d]);
    if (!nn_st_mul_u64(n, e->shape[d], &n))
      return core_fail(err, NBRDF_ERR_FORMAT, "tensor '%s' has shape %s whose size overflows",
                       e->name, shape);
  }
  if (!nn_st_mul_u64(n, elem, &bytes))
    return core_fail(err, NBRDF_ERR_FORMAT, "tensor '%s' has shape %s whose size overflows",
                     e->name, shape);
  if (e->begin > e->end)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "tensor '%s' has data_offsets [%llu, %llu] that end "
                     "before they begin",
                     e->name, (ull)e->begin, (ull)e->end);
  if (bytes != e->end - e->begin)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "tensor '%s' (%s, shape %s) needs %llu bytes but its data_offsets "
                     "[%llu, %llu] span %llu",
                     e->name, e->dtype, shape, (ull)bytes, (ull)e->begin, (ull)e->end,
                     (ull)(e->end - e->begin));
  if (e->end > data_size)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "tensor '%s' has data_offsets [%llu, %llu] past the "
                     "end of the data buffer (%llu bytes; truncated file?)",
                     e->name, (ull)e->begin, (ull)e->end, (ull)data_size);
  *count = n;
  return NBRDF_OK;
}

/* The spec requires the tensors to tile the data buffer exactly. */
static nbrdf_status check_coverage(const nn_st_header *h, uint64_t data_size, nbrdf_error *err) {
  if (h->count == 0) {
    if (data_size == 0) return NBRDF_OK;
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "%llu trailing bytes after the header, which lists "
                     "no tensor",
                     (ull)data_size);
  }
  const nn_st_entry **order = malloc(h->count * sizeof *order);
  if (!order) return core_fail(err, NBRDF_ERR_MEMORY, "out of memory checking offsets");
  for (size_t i = 0; i < h->count; i++)
    order[i] = &h->entries[i];
  qsort(order, h->count, sizeof *order, compare_entry_offsets);
  nbrdf_status st = NBRDF_OK;
  uint64_t covered = 0;
  for (size_t i = 0; i < h->count && !st; i++) {
    const nn_st_entry *e = order[i];
    if (e->begin < covered)
      st = core_fail(err, NBRDF_ERR_FORMAT,
                     "tensors '%s' and '%s' overlap in the data buffer "
                     "(data_offsets [%llu, %llu] and [%llu, %llu])",
                     order[i - 1]->name, e->name, (ull)order[i - 1]->begin, (ull)order[i - 1]->end,
                     (ull)e->begin, (ull)e->end);
    else if (e->begin > covered)
      st = core_fail(err, NBRDF_ERR_FORMAT,
                     "bytes [%llu, %llu) of the data buffer belong to no "
                     "tensor (a hole before '%s')",
                     (ull)covered, (ull)e->begin, e->name);
    covered = e->end;
  }
  free(order);
  if (!st && covered < data_size)
    st = core_fail(err, NBRDF_ERR_FORMAT, "%llu trailing bytes after the last tensor's data",
                   (ull)(data_size - covered));
  return st;
}

static nbrdf_status load(nn_st_reader *r, const unsigned char *bytes, size_t size,
                         nbrdf_error *err) {
  if (size < 8)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "file of %zu bytes is too short for the 8-byte "
                     "header length (truncated?)",
                     size);
  uint64_t n = 0;
  for (int k = 7; k >= 0; k--)
    n = n << 8 | bytes[k];
  if (n > size - 8)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "header length %llu runs past the end of the file "
                     "(%zu bytes; truncated?)",
                     (ull)n, size);
  if (n > ST_MAX_HEADER)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "header length %llu exceeds the format's limit of "
                     "%llu bytes",
                     (ull)n, (ull)ST_MAX_HEADER);
  const unsigned char *json = bytes + 8;
  if (n == 0 || json[0] != '{')
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "header does not start with '{' "
                     "(not a safetensors file?)");
  size_t bad = nn_st_utf8_invalid_at(json, (size_t)n);
  if (bad < n)
    return core_fail(err, NBRDF_ERR_FORMAT, "header is not valid UTF-8 (at header byte %zu)", bad);
  nn_st_header *h = &r->header;
  nbrdf_status st = nn_st_parse_header((const char *)json, (size_t)n, h, err);
  if (st) return st;

  const unsigned char *data = json + n;
  uint64_t data_size = size - 8 - n, total = 0;
  nn_st_dtype *dtypes = calloc(h->count + 1, sizeof *dtypes);
  uint64_t *counts = calloc(h->count + 1, sizeof *counts);
  if (!dtypes || !counts) st = core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
  for (size_t i = 0; i < h->count && !st; i++) {
    st = check_entry(&h->entries[i], data_size, &dtypes[i], &counts[i], err);
    total += counts[i]; /* counts[i] <= data_size / 2: no overflow */
  }
  free(dtypes);
  free(counts);
  if (st) return st;

  if (h->count) qsort(h->entries, h->count, sizeof *h->entries, compare_entry_names);
  for (size_t i = 1; i < h->count; i++)
    if (strcmp(h->entries[i - 1].name, h->entries[i].name) == 0)
      return core_fail(err, NBRDF_ERR_FORMAT, "tensor name '%s' appears twice", h->entries[i].name);
  if (h->meta_count) qsort(h->meta, h->meta_count, sizeof *h->meta, compare_meta_keys);
  for (size_t i = 1; i < h->meta_count; i++)
    if (strcmp(h->meta[i - 1].key, h->meta[i].key) == 0)
      return core_fail(err, NBRDF_ERR_FORMAT, "metadata key '%s' appears twice", h->meta[i].key);
  if ((st = check_coverage(h, data_size, err))) return st;

  /* Only now that every size is backed by real bytes is anything large allocated. */
  r->tensors = calloc(h->count + 1, sizeof *r->tensors);
  r->values = total ? malloc((size_t)total * sizeof(float)) : NULL;
  if (!r->tensors || (total && !r->values))
    return core_fail(err, NBRDF_ERR_MEMORY, "out of memory for %llu values", (ull)total);
  size_t next = 0;
  for (size_t i = 0; i < h->count; i++) {
    const nn_st_entry *e = &h->entries[i];
    nn_st_tensor *t = &r->tensors[i];
    size_t elem = 0;
    nn_st_dtype_lookup(e->dtype, &t->dtype, &elem);
    t->name = e->name;
    t->ndim = e->ndim;
    t->count = 1;
    for (int d = 0; d < e->ndim; d++)
      t->count *= (size_t)e->shape[d];
    for (int d = 0; d < e->ndim; d++)
      t->shape[d] = (int64_t)e->shape[d];
    if (t->count) {
      float *dst = r->values + next;
      nn_st_convert(t->dtype, data + e->begin, t->count, dst);
      t->data = dst;
      next += t->count;
    }
  }
  r->checksum = nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, bytes, size);
  return NBRDF_OK;
}

nbrdf_status nn_st_open_memory(const void *bytes, size_t size, const char *label,
                               nn_st_reader **out, nbrdf_error *err) {
  if (!out) return core_fail(err, NBRDF_ERR_ARGUMENT, "nn_st_open_memory: out is NULL");
  *out = NULL;
  if (!label) label = "<memory>";
  if (!bytes && size)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: no bytes given for a size of %zu", label, size);
  nn_st_reader *r = calloc(1, sizeof *r);
  char *copy = strdup(label);
  if (!r || !copy) {
    free(r);
    free(copy);
    return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", label);
  }
  r->label = copy;
  nbrdf_status st = load(r, bytes, size, err);
  if (st) {
    core_error_prefix(err, "%s: ", label);
    nn_st_close(r);
    return st;
  }
  *out = r;
  return NBRDF_OK;
}

static nbrdf_status io_error(nbrdf_error *err, const char *path, const char *what, int code) {
  char reason[128] = "unknown error";
  if (strerror_r(code, reason, sizeof reason) != 0)
    snprintf(reason, sizeof reason, "errno %d", code);
  return core_fail(err, NBRDF_ERR_IO, "%s: %s: %s", path, what, reason);
}

nbrdf_status nn_st_open(const char *path, nn_st_reader **out, nbrdf_error *err) {
  if (!path || !out) return core_fail(err, NBRDF_ERR_ARGUMENT, "nn_st_open: NULL argument");
  *out = NULL;
  /* Regular files only (a FIFO would block, a device never end), and the
   * size comes from stat before anything is allocated. */
  int fd = -1;
  uint64_t file_size = 0;
  nbrdf_status opened = core_input_open(path, NBRDF_ST_FILE_MAX, &fd, &file_size, err);
  if (opened != NBRDF_OK) return opened;
  size_t size = (size_t)file_size, done = 0;
  unsigned char *bytes = malloc(size ? size : 1);
  if (!bytes) {
    close(fd);
    return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory for %zu bytes", path, size);
  }
  while (done < size) {
    ssize_t got = read(fd, bytes + done, size - done);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      int code = got < 0 ? errno : 0;
      free(bytes);
      close(fd);
      if (code) return io_error(err, path, "cannot read", code);
      return core_fail(err, NBRDF_ERR_IO, "%s: file shrank while being read", path);
    }
    done += (size_t)got;
  }
  close(fd);
  nbrdf_status st = nn_st_open_memory(bytes, size, path, out, err);
  free(bytes);
  return st;
}

void nn_st_close(nn_st_reader *r) {
  if (!r) return;
  nn_st_header_free(&r->header);
  free(r->tensors);
  free(r->values);
  free(r->label);
  free(r);
}

const char *nn_st_label(const nn_st_reader *r) { return r->label; }
uint64_t nn_st_checksum(const nn_st_reader *r) { return r->checksum; }
size_t nn_st_tensor_count(const nn_st_reader *r) { return r->header.count; }

const nn_st_tensor *nn_st_tensor_at(const nn_st_reader *r, size_t index) {
  return index < r->header.count ? &r->tensors[index] : NULL;
}

const nn_st_tensor *nn_st_find(const nn_st_reader *r, const char *name) {
  size_t lo = 0, hi = r->header.count;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    int c = strcmp(r->tensors[mid].name, name);
    if (c == 0) return &r->tensors[mid];
    if (c < 0)
      lo = mid + 1;
    else
      hi = mid;
  }
  return NULL;
}

nbrdf_status nn_st_expect(const nn_st_reader *r, const char *name, int ndim, const int64_t *shape,
                          const float **data, nbrdf_error *err) {
  if (!r || !name || ndim < 0 || ndim > NBRDF_ST_MAX_DIMS || (ndim > 0 && !shape))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "nn_st_expect: invalid arguments");
  uint64_t want[NBRDF_ST_MAX_DIMS] = {0}, have[NBRDF_ST_MAX_DIMS] = {0};
  for (int d = 0; d < ndim; d++) {
    if (shape[d] < 0)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "nn_st_expect: negative dimension for '%s'", name);
    want[d] = (uint64_t)shape[d];
  }
  const nn_st_tensor *t = nn_st_find(r, name);
  if (!t) return core_fail(err, NBRDF_ERR_MISMATCH, "%s: has no tensor '%s'", r->label, name);
  int same = t->ndim == ndim;
  for (int d = 0; d < t->ndim; d++)
    have[d] = (uint64_t)t->shape[d];
  for (int d = 0; same && d < ndim; d++)
    same = have[d] == want[d];
  if (!same) {
    char got_s[160], want_s[160];
    nn_st_format_shape(got_s, sizeof got_s, t->ndim, have);
    nn_st_format_shape(want_s, sizeof want_s, ndim, want);
    return core_fail(err, NBRDF_ERR_MISMATCH, "%s: tensor '%s' has shape %s, expected %s", r->label,
                     name, got_s, want_s);
  }
  for (size_t i = 0; i < t->count; i++)
    if (!isfinite(t->data[i]))
      return core_fail(err, NBRDF_ERR_FORMAT, "%s: tensor '%s' holds %s at flat index %zu",
                       r->label, name, isnan(t->data[i]) ? "NaN" : "an infinity", i);
  if (data) *data = t->data;
  return NBRDF_OK;
}

nbrdf_status nn_st_expect_copy(const nn_st_reader *r, const char *name, int ndim,
                               const int64_t *shape, float *dst, nbrdf_error *err) {
  const float *src = NULL;
  nbrdf_status st = nn_st_expect(r, name, ndim, shape, &src, err);
  if (st) return st;
  const nn_st_tensor *t = nn_st_find(r, name);
  if (t->count) memcpy(dst, src, t->count * sizeof(float));
  return NBRDF_OK;
}

size_t nn_st_metadata_count(const nn_st_reader *r) { return r->header.meta_count; }

const char *nn_st_metadata_key(const nn_st_reader *r, size_t index) {
  return index < r->header.meta_count ? r->header.meta[index].key : NULL;
}

const char *nn_st_metadata_value(const nn_st_reader *r, size_t index) {
  return index < r->header.meta_count ? r->header.meta[index].value : NULL;
}

const char *nn_st_metadata_get(const nn_st_reader *r, const char *key) {
  size_t lo = 0, hi = r->header.meta_count;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    int c = strcmp(r->header.meta[mid].key, key);
    if (c == 0) return r->header.meta[mid].value;
    if (c < 0)
      lo = mid + 1;
    else
      hi = mid;
  }
  return NULL;
}

nbrdf_status nn_st_metadata_require(const nn_st_reader *r, const char *key, const char **value,
                                    nbrdf_error *err) {
  const char *v = nn_st_metadata_get(r, key);
  if (!v) return core_fail(err, NBRDF_ERR_MISMATCH, "%s: metadata has no key '%s'", r->label, key);
  if (value) *value = v;
  return NBRDF_OK;
}
