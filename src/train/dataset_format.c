#include "train/dataset_format.h"

#include <string.h>

#include "nn/safetensors.h"

void train_ds_put_u32(unsigned char *p, uint32_t v) {
  for (int i = 0; i < 4; i++)
    p[i] = (unsigned char)(v >> (8 * i));
}
void train_ds_put_u64(unsigned char *p, uint64_t v) {
  for (int i = 0; i < 8; i++)
    p[i] = (unsigned char)(v >> (8 * i));
}
uint32_t train_ds_get_u32(const unsigned char *p) {
  uint32_t v = 0;
  for (int i = 0; i < 4; i++)
    v |= (uint32_t)p[i] << (8 * i);
  return v;
}
uint64_t train_ds_get_u64(const unsigned char *p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; i++)
    v |= (uint64_t)p[i] << (8 * i);
  return v;
}
static void put_f64(unsigned char *p, double x) {
  uint64_t v;
  memcpy(&v, &x, 8);
  train_ds_put_u64(p, v);
}
static void put_f32(unsigned char *p, float x) {
  uint32_t v;
  memcpy(&v, &x, 4);
  train_ds_put_u32(p, v);
}
double train_ds_get_f64(const unsigned char *p) {
  uint64_t v = train_ds_get_u64(p);
  double x;
  memcpy(&x, &v, 8);
  return x;
}
float train_ds_get_f32(const unsigned char *p) {
  uint32_t v = train_ds_get_u32(p);
  float x;
  memcpy(&x, &v, 4);
  return x;
}

size_t train_ds_record_bytes(const train_dataset_settings *s) {
  return TRAIN_DS_RECORD_HEAD_BYTES +
         (size_t)s->incident * (size_t)s->outgoing * TRAIN_DATASET_FLOATS * 4 + 8;
}

void train_ds_encode_header(const train_dataset_settings *s,
                            unsigned char out[TRAIN_DS_HEADER_BYTES]) {
  memset(out, 0, TRAIN_DS_HEADER_BYTES);
  memcpy(out, TRAIN_DS_MAGIC, 8);
  /* Version 2 keeps the draws in the upper half of the kind word. */
  int v2 = s->draws != TRAIN_DRAWS_TABLE2;
  train_ds_put_u32(out + 8, v2 ? TRAIN_DATASET_VERSION_DRAWS : TRAIN_DATASET_VERSION);
  train_ds_put_u32(out + 12, (uint32_t)s->kind | (v2 ? (uint32_t)s->draws << 16 : 0u));
  train_ds_put_u64(out + 16, s->count);
  train_ds_put_u64(out + 24, s->seed);
  train_ds_put_u32(out + 32, (uint32_t)s->incident);
  train_ds_put_u32(out + 36, (uint32_t)s->outgoing);
  train_ds_put_u32(out + 40, (uint32_t)s->sampled);
  train_ds_put_u32(out + 44, (uint32_t)s->spp);
  train_ds_put_u32(out + 48, TRAIN_DATASET_PARAMS);
  train_ds_put_u32(out + 52, TRAIN_DATASET_FLOATS);
  train_ds_put_u64(out + 56, nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, out, 56));
}

int train_ds_decode_header(const unsigned char in[TRAIN_DS_HEADER_BYTES], train_dataset_settings *s,
                           const char **why) {
  if (memcmp(in, TRAIN_DS_MAGIC, 8) != 0) return *why = "not an nbrdf data set (bad magic)", 0;
  if (train_ds_get_u64(in + 56) != nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, in, 56))
    return *why = "header checksum mismatch", 0;
  uint32_t version = train_ds_get_u32(in + 8);
  if (version != TRAIN_DATASET_VERSION && version != TRAIN_DATASET_VERSION_DRAWS)
    return *why = "unsupported version", 0;
  if (train_ds_get_u32(in + 48) != TRAIN_DATASET_PARAMS ||
      train_ds_get_u32(in + 52) != TRAIN_DATASET_FLOATS)
    return *why = "unexpected record layout", 0;
  uint32_t kind = train_ds_get_u32(in + 12), draws = 0, k = train_ds_get_u32(in + 32),
           m = train_ds_get_u32(in + 36), sampled = train_ds_get_u32(in + 40),
           spp = train_ds_get_u32(in + 44);
  if (version == TRAIN_DATASET_VERSION_DRAWS) {
    draws = kind >> 16, kind &= 0xffffu;
    if (draws != TRAIN_DRAWS_COVERAGE && draws != TRAIN_DRAWS_TAILS && draws != TRAIN_DRAWS_MIRROR)
      return *why = "unknown parameter distribution", 0;
  }
  if (kind > TRAIN_SINGLE || k < 1 || k > 4096 || m < 1 || m > 65536 || sampled > m || spp < 2 ||
      spp > (1u << 30))
    return *why = "header settings out of range", 0;
  memset(s, 0, sizeof *s);
  s->kind = (train_kind)kind;
  s->draws = (train_draws)draws;
  s->count = train_ds_get_u64(in + 16);
  s->seed = train_ds_get_u64(in + 24);
  s->incident = (int)k;
  s->outgoing = (int)m;
  s->sampled = (int)sampled;
  s->spp = (int)spp;
  return 1;
}

void train_ds_encode_record(const train_dataset_settings *s, uint64_t index, const train_params *p,
                            const float *samples, unsigned char *out) {
  train_ds_put_u64(out, index);
  train_ds_put_u32(out + 8, (uint32_t)p->kind);
  train_ds_put_u32(out + 12, (uint32_t)p->n_coats);
  double v[TRAIN_DATASET_PARAMS];
  for (int c = 0; c < 2; c++) {
    v[4 * c + 0] = p->coat[c].alpha;
    v[4 * c + 1] = p->coat[c].eta;
    v[4 * c + 2] = p->coat[c].albedo;
    v[4 * c + 3] = p->coat[c].sigma_t;
  }
  v[8] = p->base_alpha;
  v[9] = p->base_r0;
  v[10] = p->base_eta;
  for (int i = 0; i < TRAIN_DATASET_PARAMS; i++)
    put_f64(out + 16 + 8 * i, v[i]);
  size_t n = (size_t)s->incident * (size_t)s->outgoing * TRAIN_DATASET_FLOATS;
  unsigned char *q = out + TRAIN_DS_RECORD_HEAD_BYTES;
  for (size_t i = 0; i < n; i++)
    put_f32(q + 4 * i, samples[i]);
  size_t body = TRAIN_DS_RECORD_HEAD_BYTES + 4 * n;
  train_ds_put_u64(out + body, nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, out, body));
}

void train_ds_encode_footer(uint64_t count, uint64_t checksum,
                            unsigned char out[TRAIN_DS_FOOTER_BYTES]) {
  memcpy(out, TRAIN_DS_FOOTER_MAGIC, 8);
  train_ds_put_u64(out + 8, count);
  train_ds_put_u64(out + 16, checksum);
}
