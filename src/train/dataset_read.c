/* Reading and validating a data set file (docs/DATASET.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/error.h"
#include "core/input_file.h"
#include "nn/safetensors.h"
#include "train/dataset.h"
#include "train/dataset_format.h"

static void decode_params(const unsigned char *in, train_params *p) {
  memset(p, 0, sizeof *p);
  p->kind = (train_kind)train_ds_get_u32(in + 8);
  p->n_coats = (int)train_ds_get_u32(in + 12);
  double v[TRAIN_DATASET_PARAMS];
  for (int i = 0; i < TRAIN_DATASET_PARAMS; i++)
    v[i] = train_ds_get_f64(in + 16 + 8 * i);
  for (int c = 0; c < 2; c++) {
    p->coat[c].alpha = v[4 * c + 0];
    p->coat[c].eta = v[4 * c + 1];
    p->coat[c].albedo = v[4 * c + 2];
    p->coat[c].sigma_t = v[4 * c + 3];
  }
  p->base_alpha = v[8];
  p->base_r0 = v[9];
  p->base_eta = v[10];
}

/* Why record `rec` (already checksummed) is invalid, or NULL. */
static const char *check_record(const train_dataset_settings *s, uint64_t family, uint64_t i,
                                const unsigned char *rec, train_params *p, float *samples,
                                size_t *bad_sample) {
  if (train_ds_get_u64(rec) != i) return "wrong index";
  decode_params(rec, p);
  train_params want;
  train_params_draw_from(family, s->kind, s->draws, i, &want);
  if (memcmp(p, &want, sizeof want) != 0)
    return "parameters differ from those the header's seed draws";
  size_t n = (size_t)s->incident * (size_t)s->outgoing;
  const unsigned char *q = rec + TRAIN_DS_RECORD_HEAD_BYTES;
  for (size_t j = 0; j < n * TRAIN_DATASET_FLOATS; j++)
    samples[j] = train_ds_get_f32(q + 4 * j);
  for (size_t j = 0; j < n; j++) {
    const float *x = samples + TRAIN_DATASET_FLOATS * j;
    *bad_sample = j;
    for (int d = 0; d < 2; d++) {
      const float *w = x + 3 * d;
      double len = sqrt((double)w[0] * w[0] + (double)w[1] * w[1] + (double)w[2] * w[2]);
      if (!(w[2] > 0.0f) || !(fabs(len - 1.0) < 1e-5)) return "direction not unit with z > 0";
    }
    if (!isfinite(x[6]) || x[6] < 0.0f) return "f is negative or not finite";
    if (!isfinite(x[7]) || x[7] < 0.0f) return "f_stderr is negative or not finite";
  }
  return NULL;
}

nbrdf_status train_dataset_read(const char *path, int strict, train_dataset_info *info,
                                train_dataset_record_fn on_record, void *user, nbrdf_error *err) {
  memset(info, 0, sizeof *info);
  int fd = -1;
  nbrdf_status opened = core_input_open(path, NBRDF_INPUT_ANY_SIZE, &fd, NULL, err);
  if (opened != NBRDF_OK) return opened;
  FILE *f = fdopen(fd, "rb");
  if (!f) {
    close(fd);
    return core_fail(err, NBRDF_ERR_IO, "%s: cannot open for reading", path);
  }
  unsigned char head[TRAIN_DS_HEADER_BYTES];
  const char *why = "truncated header";
  if (fread(head, 1, sizeof head, f) != sizeof head ||
      !train_ds_decode_header(head, &info->settings, &why)) {
    fclose(f);
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: %s", path, why);
  }
  const train_dataset_settings *s = &info->settings;
  uint64_t family = train_family_seed(s->seed);
  size_t rb = train_ds_record_bytes(s), n = (size_t)s->incident * (size_t)s->outgoing;
  unsigned char *rec = malloc(rb);
  float *samples = malloc(n * TRAIN_DATASET_FLOATS * sizeof *samples);
  if (!rec || !samples) {
    free(rec), free(samples), fclose(f);
    return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory for a %zu-byte record", path, rb);
  }
  uint64_t sum = nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, head, sizeof head);
  info->valid_bytes = TRAIN_DS_HEADER_BYTES;
  nbrdf_status st = NBRDF_OK;
  why = NULL;
  uint64_t i = 0;
  size_t bad_sample = 0;
  for (; i < s->count; i++) {
    size_t got = fread(rec, 1, rb, f);
    if (got != rb) {
      why = got == 0 ? "missing: the file is unfinished (resume it)" : "truncated";
      break;
    }
    if (train_ds_get_u64(rec + rb - 8) != nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, rec, rb - 8)) {
      why = "checksum mismatch";
      break;
    }
    train_dataset_record r = {i, {0}, n, samples};
    why = check_record(s, family, i, rec, &r.params, samples, &bad_sample);
    if (why) {
      if (strict)
        st = core_fail(err, NBRDF_ERR_FORMAT, "%s: record %llu (sample %zu): %s", path,
                       (unsigned long long)i, bad_sample, why);
      break;
    }
    sum = nn_st_fnv1a64(sum, rec, rb);
    info->records = i + 1;
    info->valid_bytes += rb;
    if (on_record && on_record(user, &r)) break;
  }
  if (!st && why && strict)
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: record %llu of %llu: %s", path,
                   (unsigned long long)i, (unsigned long long)s->count, why);
  if (!st && !why && info->records == s->count) {
    unsigned char foot[TRAIN_DS_FOOTER_BYTES + 1];
    size_t got = fread(foot, 1, sizeof foot, f);
    if (got == TRAIN_DS_FOOTER_BYTES && memcmp(foot, TRAIN_DS_FOOTER_MAGIC, 8) == 0 &&
        train_ds_get_u64(foot + 8) == s->count && train_ds_get_u64(foot + 16) == sum) {
      info->complete = 1;
      info->checksum = sum;
    } else if (strict) {
      st = core_fail(err, NBRDF_ERR_FORMAT, "%s: %s", path,
                     got == 0                      ? "footer missing (an unfinished file?)"
                     : got > TRAIN_DS_FOOTER_BYTES ? "trailing bytes after the footer"
                     : got < TRAIN_DS_FOOTER_BYTES ? "truncated footer"
                                                   : "footer checksum or count mismatch");
    }
  }
  info->prefix_checksum = sum;
  free(rec), free(samples), fclose(f);
  return st;
}
