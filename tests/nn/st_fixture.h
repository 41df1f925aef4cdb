/* Helpers shared by the safetensors tests: build files byte by byte, as the reference
 * implementation lays them out. */
#ifndef NBRDF_TESTS_ST_FIXTURE_H
#define NBRDF_TESTS_ST_FIXTURE_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "nn/safetensors.h"

/* 8-byte little-endian `header_len`, then `json` (padded with spaces to header_len; pass
 * header_len 0 to use strlen(json) rounded up to 8 as safetensors does), then `data`. */
static inline unsigned char *st_build_raw(const char *json, uint64_t header_len, const void *data,
                                          size_t data_size, size_t *size) {
  size_t jlen = strlen(json);
  if (header_len == 0) header_len = (jlen + 7) / 8 * 8;
  size_t pad = header_len > jlen ? (size_t)header_len - jlen : 0;
  size_t body = jlen + pad;
  *size = 8 + body + data_size;
  unsigned char *out = malloc(*size + 1);
  for (int k = 0; k < 8; k++)
    out[k] = (unsigned char)(header_len >> (8 * k));
  memcpy(out + 8, json, jlen);
  memset(out + 8 + jlen, ' ', pad);
  if (data_size) memcpy(out + 8 + body, data, data_size);
  return out;
}

/* A file whose header is `json` (padded) and whose data buffer is `data_size` bytes of a
 * counting pattern. */
static inline unsigned char *st_build(const char *json, size_t data_size, size_t *size) {
  unsigned char *data = malloc(data_size + 1);
  for (size_t i = 0; i < data_size; i++)
    data[i] = (unsigned char)(i * 7 + 1);
  unsigned char *out = st_build_raw(json, 0, data, data_size, size);
  free(data);
  return out;
}

/* Opens a hand-built file from memory under the label "t.safetensors". */
static inline nbrdf_status st_open_json(const char *json, size_t data_size, nbrdf_error *err,
                                        nn_st_reader **out) {
  size_t size = 0;
  unsigned char *bytes = st_build(json, data_size, &size);
  nn_st_reader *r = NULL;
  nbrdf_status st = nn_st_open_memory(bytes, size, "t.safetensors", &r, err);
  free(bytes);
  if (out)
    *out = r;
  else
    nn_st_close(r);
  return st;
}

#endif
