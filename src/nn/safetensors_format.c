/* The byte-level pieces of the safetensors format: dtypes, conversion to float, UTF-8,
 * the checksum. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "nn/safetensors_internal.h"

typedef struct dtype_info {
  const char *name;
  size_t size;
  int readable; /* nbrdf converts it to float */
  nn_st_dtype dtype;
} dtype_info;

/* Every dtype of the format (safetensors 0.4+); sub-byte ones have size 0 and are refused. */
static const dtype_info DTYPES[] = {
    {"F32", 4, 1, NBRDF_ST_F32},     {"F16", 2, 1, NBRDF_ST_F16},
    {"BF16", 2, 1, NBRDF_ST_BF16},   {"F64", 8, 1, NBRDF_ST_F64},
    {"BOOL", 1, 0, NBRDF_ST_F32},    {"U8", 1, 0, NBRDF_ST_F32},
    {"I8", 1, 0, NBRDF_ST_F32},      {"F8_E5M2", 1, 0, NBRDF_ST_F32},
    {"F8_E4M3", 1, 0, NBRDF_ST_F32}, {"F8_E8M0", 1, 0, NBRDF_ST_F32},
    {"I16", 2, 0, NBRDF_ST_F32},     {"U16", 2, 0, NBRDF_ST_F32},
    {"I32", 4, 0, NBRDF_ST_F32},     {"U32", 4, 0, NBRDF_ST_F32},
    {"I64", 8, 0, NBRDF_ST_F32},     {"U64", 8, 0, NBRDF_ST_F32},
    {"C64", 8, 0, NBRDF_ST_F32},     {"F4", 0, 0, NBRDF_ST_F32},
    {"F6_E2M3", 0, 0, NBRDF_ST_F32}, {"F6_E3M2", 0, 0, NBRDF_ST_F32},
};

int nn_st_dtype_lookup(const char *name, nn_st_dtype *dtype, size_t *size) {
  for (size_t i = 0; i < sizeof DTYPES / sizeof DTYPES[0]; i++) {
    if (strcmp(name, DTYPES[i].name) != 0) continue;
    if (!DTYPES[i].readable) return 0;
    *dtype = DTYPES[i].dtype;
    *size = DTYPES[i].size;
    return 1;
  }
  return -1;
}

const char *nn_st_dtype_name(nn_st_dtype dtype) {
  switch (dtype) {
  case NBRDF_ST_F32:
    return "F32";
  case NBRDF_ST_F16:
    return "F16";
  case NBRDF_ST_BF16:
    return "BF16";
  case NBRDF_ST_F64:
    return "F64";
  }
  return "?";
}

static float bits_to_float(uint32_t bits) {
  float f;
  memcpy(&f, &bits, sizeof f);
  return f;
}

/* IEEE 754 binary16 -> binary32, exact (every half is a float). */
static float half_to_float(uint16_t h) {
  uint32_t sign = (uint32_t)(h >> 15) << 31;
  uint32_t exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu;
  if (exponent == 0) { /* zero or subnormal: mantissa * 2^-24 */
    float magnitude = (float)mantissa * 0x1p-24f;
    return sign ? -magnitude : magnitude;
  }
  if (exponent == 31) return bits_to_float(sign | 0x7f800000u | (mantissa << 13));
  return bits_to_float(sign | ((exponent + 112u) << 23) | (mantissa << 13));
}

/* Rounds to nearest; values beyond float's range become +-inf rather than the undefined
 * behaviour C gives an out-of-range conversion. */
static float double_to_float(double d) {
  if (isfinite(d) && fabs(d) > (double)FLT_MAX) {
    /* Values within half an ulp above FLT_MAX round to FLT_MAX. */
    double limit = (double)FLT_MAX + ldexp(1.0, 127 - 24);
    if (fabs(d) < limit) return d < 0 ? -FLT_MAX : FLT_MAX;
    return d < 0 ? -INFINITY : INFINITY;
  }
  return (float)d;
}

static uint16_t load_u16(const unsigned char *p) { return (uint16_t)(p[0] | (p[1] << 8)); }

static uint32_t load_u32(const unsigned char *p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

void nn_st_convert(nn_st_dtype dtype, const unsigned char *src, size_t count, float *dst) {
  switch (dtype) {
  case NBRDF_ST_F32:
    for (size_t i = 0; i < count; i++)
      dst[i] = bits_to_float(load_u32(src + 4 * i));
    break;
  case NBRDF_ST_F16:
    for (size_t i = 0; i < count; i++)
      dst[i] = half_to_float(load_u16(src + 2 * i));
    break;
  case NBRDF_ST_BF16: /* bfloat16 is the upper half of a binary32 */
    for (size_t i = 0; i < count; i++)
      dst[i] = bits_to_float((uint32_t)load_u16(src + 2 * i) << 16);
    break;
  case NBRDF_ST_F64:
    for (size_t i = 0; i < count; i++) {
      uint64_t bits = load_u32(src + 8 * i) | (uint64_t)load_u32(src + 8 * i + 4) << 32;
      double d;
      memcpy(&d, &bits, sizeof d);
      dst[i] = double_to_float(d);
    }
    break;
  }
}

size_t nn_st_utf8_invalid_at(const unsigned char *s, size_t size) {
  size_t i = 0;
  while (i < size) {
    unsigned c = s[i];
    if (c < 0x80) {
      i++;
      continue;
    }
    size_t len;
    uint32_t cp, min;
    if ((c & 0xe0u) == 0xc0u)
      len = 2, cp = c & 0x1fu, min = 0x80;
    else if ((c & 0xf0u) == 0xe0u)
      len = 3, cp = c & 0x0fu, min = 0x800;
    else if ((c & 0xf8u) == 0xf0u)
      len = 4, cp = c & 0x07u, min = 0x10000;
    else
      return i;
    if (size - i < len) return i;
    for (size_t k = 1; k < len; k++) {
      unsigned d = s[i + k];
      if ((d & 0xc0u) != 0x80u) return i;
      cp = cp << 6 | (d & 0x3fu);
    }
    if (cp < min || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return i;
    i += len;
  }
  return size;
}

void nn_st_format_shape(char *buf, size_t size, int ndim, const uint64_t *shape) {
  size_t used = 0;
  int n = snprintf(buf, size, "[");
  used = n > 0 ? (size_t)n : 0;
  for (int i = 0; i < ndim && used < size; i++) {
    n = snprintf(buf + used, size - used, "%s%llu", i ? ", " : "", (unsigned long long)shape[i]);
    if (n < 0) break;
    used += (size_t)n;
  }
  if (used < size)
    snprintf(buf + used, size - used, "]");
  else if (size >= 4)
    memcpy(buf + size - 4, "...", 4);
}

uint64_t nn_st_fnv1a64(uint64_t hash, const void *bytes, size_t size) {
  const unsigned char *p = bytes;
  for (size_t i = 0; i < size; i++) {
    hash ^= p[i];
    hash *= UINT64_C(0x100000001b3);
  }
  return hash;
}
