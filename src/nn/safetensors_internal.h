/* Shared by the safetensors reader and writer only (src/nn/safetensors_*.c). */
#ifndef NBRDF_NN_SAFETENSORS_INTERNAL_H
#define NBRDF_NN_SAFETENSORS_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "nn/safetensors.h"

/* The reference implementation's limit on the header length. */
#define ST_MAX_HEADER UINT64_C(100000000)

/* Looks a dtype string up. Returns 1 and sets *dtype and *size for a dtype nbrdf reads,
 * 0 for a dtype of the format nbrdf refuses, -1 for an unknown string. */
int nn_st_dtype_lookup(const char *name, nn_st_dtype *dtype, size_t *size);

/* Converts `count` little-endian values of `dtype` at `src` (any alignment) to float. */
void nn_st_convert(nn_st_dtype dtype, const unsigned char *src, size_t count, float *dst);

/* Index of the first byte that is not part of valid UTF-8 (no overlongs, no surrogates,
 * nothing above U+10FFFF), or `size` if all are valid. */
size_t nn_st_utf8_invalid_at(const unsigned char *s, size_t size);

/* a * b into *out; 0 on overflow. */
static inline int nn_st_mul_u64(uint64_t a, uint64_t b, uint64_t *out) {
  if (a != 0 && b > UINT64_MAX / a) return 0;
  *out = a * b;
  return 1;
}

/* "[2, 3]" into buf (truncated with "..." if it does not fit). */
void nn_st_format_shape(char *buf, size_t size, int ndim, const uint64_t *shape);

/* One tensor entry of a header, as parsed (nothing checked beyond JSON types). */
typedef struct nn_st_entry {
  char *name;
  char *dtype;
  int ndim;
  uint64_t shape[NBRDF_ST_MAX_DIMS];
  uint64_t begin, end;
} nn_st_entry;

typedef struct nn_st_meta {
  char *key, *value;
} nn_st_meta;

typedef struct nn_st_header {
  nn_st_entry *entries;
  size_t count, cap;
  nn_st_meta *meta;
  size_t meta_count, meta_cap;
} nn_st_header;

/* Parses the JSON header (exactly `size` bytes, already checked to be UTF-8) into `out`,
 * which the caller zero-initialises and frees with nn_st_header_free even on failure.
 * Messages carry no file name (the caller prefixes it). */
nbrdf_status nn_st_parse_header(const char *json, size_t size, nn_st_header *out, nbrdf_error *err);
void nn_st_header_free(nn_st_header *header);

#endif
