#include "train/samples.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "nn/safetensors.h"

static int grow(void **p, size_t *cap, size_t need, size_t elem) {
  if (need <= *cap) return 1;
  size_t c = *cap ? *cap : 1024;
  while (c < need)
    c *= 2;
  void *q = realloc(*p, c * elem);
  if (!q) return 0;
  *p = q;
  *cap = c;
  return 1;
}

typedef struct capacity {
  size_t brdfs, rows;
} capacity;

/* Capacities live beside the struct only while loading; train_samples itself
 * stays a plain description of the data. */
static nbrdf_status append(train_samples *s, capacity *cap, const train_params *params, size_t n,
                           const float *x, nbrdf_error *err) {
  size_t rows = s->n_rows + n, c_rows = cap->rows, c_brdfs = cap->brdfs;
  size_t c_wo = c_rows, c_f = c_rows, c_off = c_brdfs, c_par = c_brdfs;
  if (!grow((void **)&s->wi, &c_rows, rows, 3 * sizeof(float)) ||
      !grow((void **)&s->wo, &c_wo, rows, 3 * sizeof(float)) ||
      !grow((void **)&s->f, &c_f, rows, sizeof(float)) ||
      !grow((void **)&s->offsets, &c_off, s->n_brdfs + 2, sizeof(size_t)) ||
      !grow((void **)&s->params, &c_par, s->n_brdfs + 1, sizeof(train_params)))
    return core_fail(err, NBRDF_ERR_MEMORY, "training samples: out of memory at %zu rows", rows);
  cap->rows = c_rows;
  cap->brdfs = c_off < c_par ? c_off : c_par;
  if (s->n_brdfs == 0) s->offsets[0] = 0;
  for (size_t j = 0; j < n; j++) {
    const float *r = x + j * TRAIN_DATASET_FLOATS;
    size_t k = s->n_rows + j;
    memcpy(s->wi + 3 * k, r, 3 * sizeof(float));
    memcpy(s->wo + 3 * k, r + 3, 3 * sizeof(float));
    s->f[k] = r[6];
  }
  s->params[s->n_brdfs] = *params;
  s->n_rows = rows;
  s->n_brdfs++;
  s->offsets[s->n_brdfs] = rows;
  return NBRDF_OK;
}

nbrdf_status train_samples_append(train_samples *s, const train_params *params, size_t n,
                                  const float *samples, nbrdf_error *err) {
  /* Exact-size growth: callers that append many BRDFs use the loader. */
  capacity cap = {s->n_brdfs, s->n_rows};
  if (n == 0) return core_fail(err, NBRDF_ERR_ARGUMENT, "training samples: a BRDF without samples");
  return append(s, &cap, params, n, samples, err);
}

typedef struct load_state {
  train_samples *s;
  capacity cap;
  uint64_t limit, taken, hash; /* records to take (0 = all), taken, FNV-1a of what was taken */
  nbrdf_status st;
  nbrdf_error *err;
} load_state;

static int on_record(void *user, const train_dataset_record *r) {
  load_state *ls = user;
  if (ls->limit && ls->taken == ls->limit) return 1;
  ls->st = append(ls->s, &ls->cap, &r->params, r->n_samples, r->samples, ls->err);
  ls->hash = nn_st_fnv1a64(ls->hash, r->samples,
                              r->n_samples * TRAIN_DATASET_FLOATS * sizeof(float));
  ls->taken++;
  return ls->st != NBRDF_OK;
}

/* "path" or "path:N" (the first N records, which need not be a finished file). */
static int parse_spec(const char *spec, char *path, size_t size, uint64_t *limit) {
  const char *colon = strrchr(spec, ':');
  char *end = NULL;
  *limit = 0;
  if (colon && colon[1]) {
    unsigned long long n = strtoull(colon + 1, &end, 10);
    if (!*end && n > 0) {
      *limit = n;
      return snprintf(path, size, "%.*s", (int)(colon - spec), spec) < (int)size;
    }
  }
  return snprintf(path, size, "%s", spec) < (int)size;
}

nbrdf_status train_samples_load(int n_files, const char *const *specs, train_samples *out,
                                nbrdf_error *err) {
  memset(out, 0, sizeof *out);
  out->checksums = calloc((size_t)(n_files > 0 ? n_files : 1), sizeof(uint64_t));
  if (!out->checksums) return core_fail(err, NBRDF_ERR_MEMORY, "training samples: out of memory");
  load_state ls = {out, {0, 0}, 0, 0, 0, NBRDF_OK, err};
  for (int i = 0; i < n_files; i++) {
    char path[4096];
    train_dataset_info info;
    nbrdf_status st = NBRDF_OK;
    if (!parse_spec(specs[i], path, sizeof path, &ls.limit))
      st = core_fail(err, NBRDF_ERR_ARGUMENT, "%s: path too long", specs[i]);
    ls.taken = 0, ls.hash = NBRDF_ST_FNV1A64_INIT;
    if (!st) st = train_dataset_read(path, !ls.limit, &info, on_record, &ls, err);
    if (st == NBRDF_OK) st = ls.st;
    if (st == NBRDF_OK && ls.limit && ls.taken < ls.limit)
      st = core_fail(err, NBRDF_ERR_FORMAT, "%s: has %llu valid records, %llu were asked for", path,
                     (unsigned long long)ls.taken, (unsigned long long)ls.limit);
    if (st == NBRDF_OK && !ls.limit && !info.complete)
      st = core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: incomplete data set (%llu of %llu BRDFs); finish it with the same "
                     "`nbrdf dataset` command first, or take its first records with %s:N",
                     path, (unsigned long long)info.records,
                     (unsigned long long)info.settings.count, path);
    if (st != NBRDF_OK) {
      train_samples_free(out);
      return st;
    }
    out->checksums[i] = ls.hash;
    out->n_files = i + 1;
  }
  if (out->n_brdfs == 0) {
    train_samples_free(out);
    return core_fail(err, NBRDF_ERR_ARGUMENT, "training samples: no data set given");
  }
  return NBRDF_OK;
}

/* Samples of every BRDF, generated in parallel (each a pure function of its
 * index), appended in order. */
nbrdf_status train_samples_generate_all(train_samples *data, size_t n, const train_params *params,
                                        uint64_t family, nbrdf_error *err) {
  train_dataset_settings ds = TRAIN_DATASET_SETTINGS_DEFAULT;
  size_t per = (size_t)ds.incident * (size_t)ds.outgoing, row = per * TRAIN_DATASET_FLOATS;
  float *buf = malloc(n * row * sizeof(float));
  nbrdf_status *sts = calloc(n, sizeof *sts);
  nbrdf_error *errs = calloc(n, sizeof *errs);
  nbrdf_status st = buf && sts && errs
                        ? NBRDF_OK
                        : core_fail(err, NBRDF_ERR_MEMORY, "training samples: out of memory");
  if (!st) {
#pragma omp parallel for schedule(dynamic, 1)
    for (long k = 0; k < (long)n; k++)
      sts[k] = train_samples_generate(&ds, family, (uint64_t)k, &params[k], buf + (size_t)k * row,
                                      &errs[k]);
  }
  for (size_t k = 0; k < n && !st; k++) {
    if (sts[k]) {
      if (err) *err = errs[k];
      st = sts[k];
    } else {
      st = train_samples_append(data, &params[k], per, buf + k * row, err);
    }
  }
  free(buf), free(sts), free(errs);
  return st;
}

void train_samples_free(train_samples *s) {
  free(s->offsets);
  free(s->wi);
  free(s->wo);
  free(s->f);
  free(s->params);
  free(s->checksums);
  memset(s, 0, sizeof *s);
}

model_samples train_samples_view(const train_samples *s) {
  model_samples m = {s->n_brdfs, s->offsets, s->wi, s->wo, s->f, NULL};
  return m;
}
