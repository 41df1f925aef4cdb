/* Writing safetensors: deterministic bytes (tensors sorted by name, metadata by key, the
 * header padded with spaces to 8 bytes, as the reference implementation writes them) and an
 * atomic save (core/output_file.h). */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/output_file.h"
#include "nn/safetensors_internal.h"

typedef struct wtensor {
  char *name;
  int ndim;
  uint64_t shape[NBRDF_ST_MAX_DIMS];
  size_t count;
  const float *data; /* borrowed, or == owned */
  float *owned;
} wtensor;

struct nn_st_writer {
  wtensor *tensors;
  size_t count, cap;
  nn_st_meta *meta;
  size_t meta_count, meta_cap;
};

nbrdf_status nn_st_writer_create(nn_st_writer **out, nbrdf_error *err) {
  if (!out) return core_fail(err, NBRDF_ERR_ARGUMENT, "nn_st_writer_create: out is NULL");
  *out = calloc(1, sizeof **out);
  return *out ? NBRDF_OK : core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
}

void nn_st_writer_destroy(nn_st_writer *w) {
  if (!w) return;
  for (size_t i = 0; i < w->count; i++) {
    free(w->tensors[i].name);
    free(w->tensors[i].owned);
  }
  for (size_t i = 0; i < w->meta_count; i++) {
    free(w->meta[i].key);
    free(w->meta[i].value);
  }
  free(w->tensors);
  free(w->meta);
  free(w);
}

/* A string the header can carry: non-empty (for names), UTF-8. */
static nbrdf_status check_text(const char *s, const char *what, nbrdf_error *err) {
  if (!s) return core_fail(err, NBRDF_ERR_ARGUMENT, "%s is NULL", what);
  size_t n = strlen(s);
  if (nn_st_utf8_invalid_at((const unsigned char *)s, n) < n)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s '%s' is not valid UTF-8", what, s);
  return NBRDF_OK;
}

static nbrdf_status add(nn_st_writer *w, const char *name, int ndim, const int64_t *shape,
                        const float *data, int copy, nbrdf_error *err) {
  if (!w) return core_fail(err, NBRDF_ERR_ARGUMENT, "nn_st_writer_add: writer is NULL");
  nbrdf_status st = check_text(name, "tensor name", err);
  if (st) return st;
  if (!name[0] || strcmp(name, "__metadata__") == 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "'%s' cannot name a tensor", name);
  if (ndim < 0 || ndim > NBRDF_ST_MAX_DIMS || (ndim > 0 && !shape))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "tensor '%s': ndim %d is outside [0, %d]", name, ndim,
                     NBRDF_ST_MAX_DIMS);
  wtensor t = {0};
  uint64_t count = 1, bytes = 0;
  for (int d = 0; d < ndim; d++) {
    if (shape[d] < 0)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "tensor '%s': dimension %d is negative", name, d);
    t.shape[d] = (uint64_t)shape[d];
    if (!nn_st_mul_u64(count, t.shape[d], &count))
      return core_fail(err, NBRDF_ERR_ARGUMENT, "tensor '%s': size overflows", name);
  }
  if (!nn_st_mul_u64(count, sizeof(float), &bytes) || bytes > SIZE_MAX / 2)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "tensor '%s': size overflows", name);
  if (count && !data) return core_fail(err, NBRDF_ERR_ARGUMENT, "tensor '%s': data is NULL", name);
  for (size_t i = 0; i < w->count; i++)
    if (strcmp(w->tensors[i].name, name) == 0)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "tensor '%s' was already added", name);
  if (w->count == w->cap) {
    size_t cap = w->cap ? 2 * w->cap : 16;
    wtensor *a = realloc(w->tensors, cap * sizeof *a);
    if (!a) return core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
    w->tensors = a, w->cap = cap;
  }
  t.ndim = ndim;
  t.count = (size_t)count;
  t.name = strdup(name);
  if (copy && count) {
    t.owned = malloc((size_t)bytes);
    if (t.owned) memcpy(t.owned, data, (size_t)bytes);
  }
  t.data = copy ? t.owned : data;
  if (!t.name || (copy && count && !t.owned)) {
    free(t.name);
    free(t.owned);
    return core_fail(err, NBRDF_ERR_MEMORY, "out of memory copying tensor '%s'", name);
  }
  w->tensors[w->count++] = t;
  return NBRDF_OK;
}

nbrdf_status nn_st_writer_add(nn_st_writer *w, const char *name, int ndim, const int64_t *shape,
                              const float *data, nbrdf_error *err) {
  return add(w, name, ndim, shape, data, 1, err);
}

nbrdf_status nn_st_writer_add_borrowed(nn_st_writer *w, const char *name, int ndim,
                                       const int64_t *shape, const float *data, nbrdf_error *err) {
  return add(w, name, ndim, shape, data, 0, err);
}

nbrdf_status nn_st_writer_set_metadata(nn_st_writer *w, const char *key, const char *value,
                                       nbrdf_error *err) {
  if (!w) return core_fail(err, NBRDF_ERR_ARGUMENT, "nn_st_writer_set_metadata: NULL writer");
  nbrdf_status st = check_text(key, "metadata key", err);
  if (!st) st = check_text(value, "metadata value", err);
  if (st) return st;
  char *v = strdup(value);
  if (!v) return core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
  for (size_t i = 0; i < w->meta_count; i++)
    if (strcmp(w->meta[i].key, key) == 0) {
      free(w->meta[i].value);
      w->meta[i].value = v;
      return NBRDF_OK;
    }
  char *k = strdup(key);
  if (k && w->meta_count == w->meta_cap) {
    size_t cap = w->meta_cap ? 2 * w->meta_cap : 8;
    nn_st_meta *a = realloc(w->meta, cap * sizeof *a);
    if (a) w->meta = a, w->meta_cap = cap;
  }
  if (!k || w->meta_count == w->meta_cap) {
    free(k);
    free(v);
    return core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
  }
  w->meta[w->meta_count++] = (nn_st_meta){k, v};
  return NBRDF_OK;
}

/* A growable byte buffer; `failed` sticks after the first allocation failure. */
typedef struct buf {
  char *p;
  size_t len, cap;
  int failed;
} buf;

static void put(buf *b, const char *s, size_t n) {
  if (b->failed) return;
  if (b->len + n > b->cap) {
    size_t cap = b->cap ? b->cap : 256;
    while (cap < b->len + n)
      cap *= 2;
    char *p = realloc(b->p, cap);
    if (!p) {
      b->failed = 1;
      return;
    }
    b->p = p, b->cap = cap;
  }
  memcpy(b->p + b->len, s, n);
  b->len += n;
}

static void puts_raw(buf *b, const char *s) { put(b, s, strlen(s)); }

static void put_json_string(buf *b, const char *s) {
  put(b, "\"", 1);
  for (; *s; s++) {
    unsigned char c = (unsigned char)*s;
    char esc[8];
    if (c == '"' || c == '\\') {
      esc[0] = '\\', esc[1] = (char)c;
      put(b, esc, 2);
    } else if (c < 0x20) {
      snprintf(esc, sizeof esc, "\\u%04x", c);
      put(b, esc, 6);
    } else {
      put(b, (const char *)&c, 1);
    }
  }
  put(b, "\"", 1);
}

static int compare_wtensor_names(const void *a, const void *b) {
  return strcmp((*(const wtensor *const *)a)->name, (*(const wtensor *const *)b)->name);
}

static int compare_meta_keys(const void *a, const void *b) {
  return strcmp((*(const nn_st_meta *const *)a)->key, (*(const nn_st_meta *const *)b)->key);
}

static void put_le32(unsigned char *o, uint32_t v) {
  o[0] = (unsigned char)v, o[1] = (unsigned char)(v >> 8);
  o[2] = (unsigned char)(v >> 16), o[3] = (unsigned char)(v >> 24);
}

nbrdf_status nn_st_writer_serialize(const nn_st_writer *w, void **bytes, size_t *size,
                                    nbrdf_error *err) {
  if (!w || !bytes || !size)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "nn_st_writer_serialize: NULL argument");
  *bytes = NULL, *size = 0;
  const wtensor **order = malloc((w->count + 1) * sizeof *order);
  const nn_st_meta **meta = malloc((w->meta_count + 1) * sizeof *meta);
  buf h = {0};
  if (!order || !meta) h.failed = 1;
  for (size_t i = 0; !h.failed && i < w->count; i++)
    order[i] = &w->tensors[i];
  for (size_t i = 0; !h.failed && i < w->meta_count; i++)
    meta[i] = &w->meta[i];
  if (!h.failed) {
    qsort(order, w->count, sizeof *order, compare_wtensor_names);
    qsort(meta, w->meta_count, sizeof *meta, compare_meta_keys);
  }
  puts_raw(&h, "{");
  if (w->meta_count) {
    puts_raw(&h, "\"__metadata__\":{");
    for (size_t i = 0; i < w->meta_count && !h.failed; i++) {
      if (i) puts_raw(&h, ",");
      put_json_string(&h, meta[i]->key);
      puts_raw(&h, ":");
      put_json_string(&h, meta[i]->value);
    }
    puts_raw(&h, "}");
  }
  uint64_t offset = 0;
  for (size_t i = 0; i < w->count && !h.failed; i++) {
    const wtensor *t = order[i];
    char num[64];
    if (i || w->meta_count) puts_raw(&h, ",");
    put_json_string(&h, t->name);
    puts_raw(&h, ":{\"dtype\":\"F32\",\"shape\":[");
    for (int d = 0; d < t->ndim; d++) {
      snprintf(num, sizeof num, "%s%" PRIu64, d ? "," : "", t->shape[d]);
      puts_raw(&h, num);
    }
    uint64_t end = offset + (uint64_t)t->count * 4;
    snprintf(num, sizeof num, "],\"data_offsets\":[%" PRIu64 ",%" PRIu64 "]}", offset, end);
    puts_raw(&h, num);
    offset = end;
  }
  puts_raw(&h, "}");
  while (!h.failed && h.len % 8)
    puts_raw(&h, " ");

  if (!h.failed && h.len > ST_MAX_HEADER) {
    size_t len = h.len;
    free(h.p);
    free(order);
    free(meta);
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "the header would be %zu bytes, above the "
                     "format's limit of %llu",
                     len, (unsigned long long)ST_MAX_HEADER);
  }
  unsigned char *out = NULL;
  size_t total = 0;
  if (!h.failed && offset <= SIZE_MAX - 8 - h.len) {
    total = 8 + h.len + (size_t)offset;
    out = malloc(total);
  }
  if (out) {
    put_le32(out, (uint32_t)h.len);
    put_le32(out + 4, (uint32_t)((uint64_t)h.len >> 32));
    memcpy(out + 8, h.p, h.len);
    unsigned char *o = out + 8 + h.len;
    for (size_t i = 0; i < w->count; i++)
      for (size_t k = 0; k < order[i]->count; k++, o += 4) {
        uint32_t bits;
        memcpy(&bits, &order[i]->data[k], 4);
        put_le32(o, bits);
      }
  }
  free(h.p);
  free(order);
  free(meta);
  if (!out) return core_fail(err, NBRDF_ERR_MEMORY, "out of memory serialising tensors");
  *bytes = out, *size = total;
  return NBRDF_OK;
}

nbrdf_status nn_st_writer_save(const nn_st_writer *w, const char *path, uint64_t *checksum,
                               nbrdf_error *err) {
  if (!w || !path || !path[0])
    return core_fail(err, NBRDF_ERR_ARGUMENT, "nn_st_writer_save: NULL writer or empty path");
  void *bytes = NULL;
  size_t size = 0;
  nbrdf_status st = nn_st_writer_serialize(w, &bytes, &size, err);
  if (st) {
    core_error_prefix(err, "%s: ", path);
    return st;
  }
  st = core_output_file_write_all(path, bytes, size, NULL, 0, err);
  if (!st && checksum) *checksum = nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, bytes, size);
  free(bytes);
  return st;
}
