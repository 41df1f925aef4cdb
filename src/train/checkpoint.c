#include "train/checkpoint.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

void train_checkpoint_data_key(const train_samples *data, char *out, size_t size) {
  size_t at = 0;
  out[0] = '\0';
  for (int i = 0; i < data->n_files && at + 18 < size; i++)
    at += (size_t)snprintf(out + at, size - at, "%s%016" PRIx64, i ? "," : "", data->checksums[i]);
}

uint64_t train_hash_floats(uint64_t h, const float *x, size_t n) {
  const unsigned char *b = (const unsigned char *)x;
  for (size_t i = 0; i < n * sizeof(float); i++)
    h = (h ^ b[i]) * UINT64_C(0x100000001b3);
  return h;
}

/* Every float array a checkpoint holds, in order: each group's parameters
 * and, where it has an optimiser, its Adam moments; then the further
 * tensors. Saving and loading both walk this one list. */
typedef nbrdf_status (*tensor_fn)(void *io, const char *name, size_t n, float *x, nbrdf_error *err);
static nbrdf_status each_tensor(const train_checkpoint_parts *p, tensor_fn fn, void *io,
                                nbrdf_error *err) {
  nbrdf_status st = NBRDF_OK;
  for (int g = 0; g < p->n_groups && !st; g++) {
    const trainer_group *G = &p->groups[g];
    st = fn(io, G->tensor, G->n, G->params, err);
    if (!st && p->adams[g]) st = fn(io, G->m_tensor, G->n, nn_adam_moment(p->adams[g], 0), err);
    if (!st && p->adams[g]) st = fn(io, G->v_tensor, G->n, nn_adam_moment(p->adams[g], 1), err);
  }
  for (int i = 0; i < p->n_tensors && !st; i++)
    st = fn(io, p->tensors[i].name, p->tensors[i].n, p->tensors[i].data, err);
  return st;
}

static nbrdf_status add(void *w, const char *name, size_t n, float *x, nbrdf_error *err) {
  int64_t shape[1] = {(int64_t)n};
  return nn_st_writer_add_borrowed(w, name, 1, shape, x, err);
}

nbrdf_status train_checkpoint_save(const char *path, const train_checkpoint_parts *p, int64_t step,
                                   nbrdf_error *err) {
  nn_st_writer *w = NULL;
  char text[32], key[256];
  nbrdf_status st = nn_st_writer_create(&w, err);
  snprintf(text, sizeof text, "%" PRId64, step);
  if (!st) st = nn_st_writer_set_metadata(w, "nbrdf.format", p->format, err);
  if (!st) st = nn_st_writer_set_metadata(w, "nbrdf.step", text, err);
  if (!st) st = nn_st_writer_set_metadata(w, "nbrdf.options", p->options, err);
  for (int i = 0; i < p->n_words && !st; i++) {
    snprintf(key, sizeof key, "nbrdf.state.%s", p->words[i].name);
    snprintf(text, sizeof text, "%" PRIu64, *p->words[i].value);
    st = nn_st_writer_set_metadata(w, key, text, err);
  }
  if (!st) st = each_tensor(p, add, w, err);
  if (!st) st = nn_st_writer_save(w, path, NULL, err);
  nn_st_writer_destroy(w);
  return st;
}

/* The value of `key` in an options string ("key=value\n"...), copied into
 * out; 0 when absent. */
static int option_value(const char *options, const char *key, char *out, size_t size) {
  size_t kl = strlen(key);
  for (const char *at = options; at && *at;) {
    const char *end = strchr(at, '\n');
    size_t len = end ? (size_t)(end - at) : strlen(at);
    if (len > kl && !strncmp(at, key, kl) && at[kl] == '=') {
      size_t vl = len - kl - 1 < size - 1 ? len - kl - 1 : size - 1;
      memcpy(out, at + kl + 1, vl);
      out[vl] = '\0';
      return 1;
    }
    at = end ? end + 1 : NULL;
  }
  return 0;
}

/* Every option of the run must have the checkpoint's value, and the
 * checkpoint no option the run lacks. */
static nbrdf_status compare_options(const char *label, const char *have, const char *want,
                                    nbrdf_error *err) {
  char key[128], a[1024], b[1024];
  for (int pass = 0; pass < 2; pass++) {
    const char *list = pass ? have : want;
    for (const char *at = list; at && *at;) {
      const char *eq = strchr(at, '='), *end = strchr(at, '\n');
      if (!eq || (end && eq > end)) break;
      size_t kl = (size_t)(eq - at) < sizeof key - 1 ? (size_t)(eq - at) : sizeof key - 1;
      memcpy(key, at, kl);
      key[kl] = '\0';
      int in_ckpt = option_value(have, key, a, sizeof a);
      int in_run = option_value(want, key, b, sizeof b);
      if (!in_ckpt || !in_run || strcmp(a, b))
        return core_fail(err, NBRDF_ERR_MISMATCH,
                         "%s: the checkpoint was made with %s = %s, this run has %s = %s (give "
                         "the same value, or start a new run)",
                         label, key, in_ckpt ? a : "(unset)", key, in_run ? b : "(unset)");
      at = end ? end + 1 : NULL;
    }
  }
  return NBRDF_OK;
}

static nbrdf_status take(void *r, const char *name, size_t n, float *dst, nbrdf_error *err) {
  int64_t shape[1] = {(int64_t)n};
  return nn_st_expect_copy(r, name, 1, shape, dst, err);
}

static nbrdf_status parse_u64(const nn_st_reader *r, const char *key, uint64_t *out,
                              nbrdf_error *err) {
  const char *s = nn_st_metadata_get(r, key);
  char *end = NULL;
  unsigned long long v = s && *s >= '0' && *s <= '9' ? strtoull(s, &end, 10) : 0;
  if (!s || !end || *end)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: no valid %s", nn_st_label(r), key);
  *out = (uint64_t)v;
  return NBRDF_OK;
}

nbrdf_status train_checkpoint_load(const char *path, const train_checkpoint_parts *p,
                                   const trainer_fit *fit, int64_t *step, int *legacy_used,
                                   nbrdf_error *err) {
  nn_st_reader *r = NULL;
  nbrdf_status st = nn_st_open(path, &r, err);
  if (st) return st;
  *legacy_used = 0;
  const char *fmt = nn_st_metadata_get(r, "nbrdf.format");
  const char *options = nn_st_metadata_get(r, "nbrdf.options");
  if (!fmt || strcmp(fmt, p->format))
    st = core_fail(err, NBRDF_ERR_MISMATCH,
                   "%s: a checkpoint of format '%s', this run writes '%s' (another kind of "
                   "training; give another checkpoint path)",
                   path, fmt ? fmt : "(none)", p->format);
  if (!st && options) {
    st = compare_options(path, options, p->options, err);
    uint64_t k = 0;
    if (!st) st = parse_u64(r, "nbrdf.step", &k, err);
    *step = (int64_t)k;
  } else if (!st && fit->legacy) {
    st = fit->legacy(fit->user, r, step, err);
    *legacy_used = 1;
  } else if (!st) {
    st = core_fail(err, NBRDF_ERR_MISMATCH, "%s: the checkpoint records no nbrdf.options", path);
  }
  char key[256];
  for (int i = 0; i < p->n_words && !st; i++) {
    snprintf(key, sizeof key, "nbrdf.state.%s", p->words[i].name);
    st = parse_u64(r, key, p->words[i].value, err);
  }
  if (!st) st = each_tensor(p, take, r, err);
  nn_st_close(r);
  return st;
}

nbrdf_status train_checkpoint_latents(const char *checkpoint, size_t n_brdfs, int dim,
                                      float *latents, nbrdf_error *err) {
  nn_st_reader *r = NULL;
  nbrdf_status st = nn_st_open(checkpoint, &r, err);
  if (!st) st = take(r, "latents", n_brdfs * (size_t)dim, latents, err);
  nn_st_close(r);
  return st;
}
