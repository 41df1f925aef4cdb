/* The .nbfit file (docs/FIT-FILE.md): writing and reading a fit whole. */
#include "bake/bake_fit_file.h"

#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/output_file.h"
#include "model/decoder.h"
#include "model/material.h"
#include "model/netio.h"
#include "nn/safetensors.h"

#define KEY_MAX 256

static const char *range_name(nbrdf_range_policy r) {
  return r == NBRDF_RANGE_REFUSE ? "refuse" : "clamp";
}

nbrdf_status bake_fit_decoder_checksum(const bake_fit_result *r, char hex[17], nbrdf_error *err) {
  hex[0] = '\0';
  const model_decoder *dec = r->compact.student ? r->compact.student : r->correction.decoder;
  if (!dec) return NBRDF_OK;
  void *bytes = NULL;
  size_t size = 0;
  nbrdf_status st = model_decoder_serialize(dec, &bytes, &size, err);
  if (st == NBRDF_OK)
    snprintf(hex, 17, "%016" PRIx64, nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, bytes, size));
  free(bytes);
  return st;
}

/* ---- writing ---- */

static nbrdf_status meta(nn_st_writer *w, const char *key, const char *value, nbrdf_error *err) {
  return nn_st_writer_set_metadata(w, key, value ? value : "", err);
}

static nbrdf_status meta_f(nn_st_writer *w, const char *key, nbrdf_error *err, const char *fmt,
                           ...) __attribute__((format(printf, 4, 5)));
static nbrdf_status meta_f(nn_st_writer *w, const char *key, nbrdf_error *err, const char *fmt,
                           ...) {
  char value[64];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(value, sizeof value, fmt, ap);
  va_end(ap);
  return meta(w, key, value, err);
}

/* The decoder's own safetensors tensors and metadata, each name under `prefix`. */
static nbrdf_status add_decoder(nn_st_writer *w, const char *prefix, const model_decoder *dec,
                                nbrdf_error *err) {
  void *bytes = NULL;
  size_t size = 0;
  nn_st_reader *r = NULL;
  nbrdf_status st = model_decoder_serialize(dec, &bytes, &size, err);
  if (st == NBRDF_OK) st = nn_st_open_memory(bytes, size, prefix, &r, err);
  free(bytes);
  char name[KEY_MAX];
  for (size_t i = 0; st == NBRDF_OK && i < nn_st_tensor_count(r); i++) {
    const nn_st_tensor *t = nn_st_tensor_at(r, i);
    snprintf(name, sizeof name, "%s%s", prefix, t->name);
    st = nn_st_writer_add(w, name, t->ndim, t->shape, t->data, err);
  }
  for (size_t i = 0; st == NBRDF_OK && i < nn_st_metadata_count(r); i++) {
    snprintf(name, sizeof name, "%s%s", prefix, nn_st_metadata_key(r, i));
    st = meta(w, name, nn_st_metadata_value(r, i), err);
  }
  nn_st_close(r);
  return st;
}

static nbrdf_status fill(nn_st_writer *w, const nbrdf_fit *f, nbrdf_error *err) {
  const bake_fit_result *r = &f->r;
  const bake_correction *c = &r->correction;
  nbrdf_status st = meta(w, "nbrdf.format", BAKE_FIT_FORMAT, err);
  if (st == NBRDF_OK) st = meta(w, "nbrdf.version", BAKE_FIT_VERSION, err);
  if (st == NBRDF_OK) st = meta(w, "nbrdf.accuracy", nbrdf_bake_accuracy_name(f->accuracy), err);
  if (st == NBRDF_OK) st = meta(w, "nbrdf.roughness", model_roughness_name(f->roughness), err);
  if (st == NBRDF_OK) st = meta(w, "nbrdf.range", range_name(f->range), err);
  if (st == NBRDF_OK)
    st = meta(w, "nbrdf.resample", f->resample == NBRDF_RESAMPLE_BILINEAR ? "bilinear" : "none",
              err);
  if (st == NBRDF_OK) st = meta_f(w, "nbrdf.quantise", err, "%d", f->quantise_bits);
  if (st == NBRDF_OK) st = meta_f(w, "nbrdf.tiles", err, "%d", f->tiles);
  if (st == NBRDF_OK) st = meta(w, "nbrdf.model_checksum", f->model_checksum, err);
  if (st == NBRDF_OK) st = meta(w, "nbrdf.base_decoder", f->base_decoder, err);
  if (st == NBRDF_OK) st = meta(w, "nbrdf.decoder_checksum", f->decoder_checksum, err);
  if (st == NBRDF_OK) st = meta_f(w, "nbrdf.latent_dim", err, "%d", c->latent_dim);
  if (st == NBRDF_OK) st = meta_f(w, "nbrdf.distinct", err, "%zu", r->distinct);
  if (st == NBRDF_OK) st = meta_f(w, "nbrdf.fitted", err, "%zu", r->fitted);
  if (st == NBRDF_OK) st = meta_f(w, "nbrdf.heldout", err, "%zu", r->heldout);
  /* %.17g: the doubles come back bit for bit (the report prints them). */
  if (st == NBRDF_OK) st = meta_f(w, "nbrdf.heldout_error", err, "%.17g", r->heldout_error);
  if (st == NBRDF_OK)
    st = meta_f(w, "nbrdf.heldout_error_fast", err, "%.17g", r->heldout_error_fast);
  if (st == NBRDF_OK) st = meta_f(w, "nbrdf.albedo_tuples", err, "%zu", r->albedo_tuples);
  if (st == NBRDF_OK) st = meta_f(w, "nbrdf.albedo_max", err, "%.17g", r->albedo_max);
  if (st == NBRDF_OK)
    st = meta_f(w, "nbrdf.albedo_max_fast", err, "%.17g", r->albedo_max_fast);
  if (st == NBRDF_OK) st = meta_f(w, "nbrdf.budget", err, "%.17g", r->budget);
  if (st == NBRDF_OK) st = meta(w, "nbrdf.attribute", r->attribute, err);
  for (int id = 0; st == NBRDF_OK && id < NBRDF_BAKE_PARAM_COUNT; id++) {
    char key[64];
    snprintf(key, sizeof key, "nbrdf.inputs.%s", model_material_param_name(id));
    st = meta(w, key, f->inputs[id], err);
  }
  const int64_t D = c->latent_dim, n = (int64_t)c->n, P = NBRDF_BAKE_PARAM_COUNT, one = 1;
  const int64_t tuples_shape[2] = {n, P}, delta_shape[2] = {n, D};
  if (st == NBRDF_OK)
    st = nn_st_writer_add_borrowed(w, "correction.tuples", 2, tuples_shape,
                                   c->tuples ? c->tuples[0].p : NULL, err);
  if (st == NBRDF_OK)
    st = nn_st_writer_add_borrowed(w, "correction.delta", 2, delta_shape, c->delta, err);
  if (st == NBRDF_OK) st = nn_st_writer_add_borrowed(w, "correction.lo", 1, &P, c->lo, err);
  if (st == NBRDF_OK) st = nn_st_writer_add_borrowed(w, "correction.hi", 1, &P, c->hi, err);
  if (st == NBRDF_OK)
    st = nn_st_writer_add_borrowed(w, "correction.radius", 1, &one, &c->radius, err);
  if (st == NBRDF_OK && c->decoder) st = add_decoder(w, "decoder/", c->decoder, err);
  const bake_compact *k = &r->compact;
  if (st == NBRDF_OK && k->student) {
    const int64_t K = k->dim, basis_shape[2] = {D, K}, project_shape[2] = {K, D};
    st = meta_f(w, "compact.dim", err, "%d", k->dim);
    if (st == NBRDF_OK) st = meta_f(w, "compact.kept", err, "%.17g", k->kept);
    if (st == NBRDF_OK) st = meta_f(w, "compact.loss_truth", err, "%.17g", k->loss_truth);
    if (st == NBRDF_OK) st = meta_f(w, "compact.loss_teacher", err, "%.17g", k->loss_teacher);
    if (st == NBRDF_OK) st = nn_st_writer_add_borrowed(w, "compact.mean", 1, &D, k->mean, err);
    if (st == NBRDF_OK)
      st = nn_st_writer_add_borrowed(w, "compact.basis", 2, basis_shape, k->basis, err);
    if (st == NBRDF_OK)
      st = nn_st_writer_add_borrowed(w, "compact.project", 2, project_shape, k->project, err);
    if (st == NBRDF_OK) st = add_decoder(w, "student/", k->student, err);
  }
  return st;
}

nbrdf_status bake_fit_file_write(nbrdf_fit *f, const char *path, const char *const *inputs,
                                 int n_inputs, nbrdf_error *err) {
  nn_st_writer *w = NULL;
  void *bytes = NULL;
  size_t size = 0;
  nbrdf_status st = nn_st_writer_create(&w, err);
  if (st == NBRDF_OK) st = fill(w, f, err);
  if (st == NBRDF_OK) st = nn_st_writer_serialize(w, &bytes, &size, err);
  nn_st_writer_destroy(w);
  if (st == NBRDF_OK)
    st = core_output_file_write_all(path, bytes, size, inputs, n_inputs, err);
  if (st == NBRDF_OK)
    snprintf(f->file_checksum, sizeof f->file_checksum, "%016" PRIx64,
             nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, bytes, size));
  free(bytes);
  return st;
}

/* ---- reading ---- */

static char *dup_text(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

/* The decoder stored under `prefix`: its tensors and metadata as a file of its own,
 * read by the decoder's reader. */
static nbrdf_status read_decoder(const nn_st_reader *r, const char *prefix, model_decoder **out,
                                 nbrdf_error *err) {
  const size_t pl = strlen(prefix);
  nn_st_writer *w = NULL;
  void *bytes = NULL;
  size_t size = 0;
  int found = 0;
  nbrdf_status st = nn_st_writer_create(&w, err);
  for (size_t i = 0; st == NBRDF_OK && i < nn_st_tensor_count(r); i++) {
    const nn_st_tensor *t = nn_st_tensor_at(r, i);
    if (strncmp(t->name, prefix, pl)) continue;
    found = 1;
    st = nn_st_writer_add_borrowed(w, t->name + pl, t->ndim, t->shape, t->data, err);
  }
  for (size_t i = 0; st == NBRDF_OK && i < nn_st_metadata_count(r); i++)
    if (!strncmp(nn_st_metadata_key(r, i), prefix, pl))
      st = nn_st_writer_set_metadata(w, nn_st_metadata_key(r, i) + pl,
                                     nn_st_metadata_value(r, i), err);
  if (st == NBRDF_OK && !found)
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: no decoder under '%s'", nn_st_label(r), prefix);
  if (st == NBRDF_OK) st = nn_st_writer_serialize(w, &bytes, &size, err);
  nn_st_writer_destroy(w);
  char label[600];
  snprintf(label, sizeof label, "%s: %.*s", nn_st_label(r), (int)(pl - 1), prefix);
  nn_st_reader *dr = NULL;
  if (st == NBRDF_OK) st = nn_st_open_memory(bytes, size, label, &dr, err);
  free(bytes);
  if (st == NBRDF_OK) st = model_decoder_read(dr, out, err);
  nn_st_close(dr);
  return st;
}

static nbrdf_status meta_size(const nn_st_reader *r, const char *key, size_t *v, nbrdf_error *err) {
  long x = 0;
  nbrdf_status st = model_meta_int(r, key, 0, 0x7fffffffffffffffL, &x, err);
  *v = (size_t)x;
  return st;
}

static nbrdf_status meta_hex(const nn_st_reader *r, const char *key, int empty_ok, char hex[17],
                             nbrdf_error *err) {
  const char *v = NULL;
  nbrdf_status st = nn_st_metadata_require(r, key, &v, err);
  if (st != NBRDF_OK) return st;
  size_t n = strlen(v);
  int ok = (n == 16 && strspn(v, "0123456789abcdef") == 16) || (empty_ok && n == 0);
  if (!ok)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: %s is '%s', not 16 hex digits", nn_st_label(r),
                     key, v);
  memcpy(hex, v, n + 1);
  return NBRDF_OK;
}

static nbrdf_status read_options(const nn_st_reader *r, nbrdf_fit *f, nbrdf_error *err) {
  const char *label = nn_st_label(r), *v = NULL;
  nbrdf_status st = nn_st_metadata_require(r, "nbrdf.accuracy", &v, err);
  int level = st == NBRDF_OK ? nbrdf_bake_accuracy_parse(v) : -1;
  if (st == NBRDF_OK && (level <= NBRDF_BAKE_FAST || level == NBRDF_BAKE_AUTO))
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: accuracy '%s' is not fitted, specialised or compact",
                     label, v);
  f->accuracy = (nbrdf_bake_accuracy)level;
  if (st == NBRDF_OK) st = nn_st_metadata_require(r, "nbrdf.roughness", &v, err);
  int rough = st == NBRDF_OK ? model_roughness_parse(v) : 0;
  if (st == NBRDF_OK && rough < 0)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: unknown roughness '%s'", label, v);
  f->roughness = (nbrdf_roughness)rough;
  if (st == NBRDF_OK) st = nn_st_metadata_require(r, "nbrdf.range", &v, err);
  if (st == NBRDF_OK && strcmp(v, "clamp") && strcmp(v, "refuse"))
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: range '%s' is not clamp or refuse", label, v);
  if (st == NBRDF_OK) f->range = strcmp(v, "refuse") ? NBRDF_RANGE_CLAMP : NBRDF_RANGE_REFUSE;
  if (st == NBRDF_OK) st = nn_st_metadata_require(r, "nbrdf.resample", &v, err);
  if (st == NBRDF_OK && strcmp(v, "none") && strcmp(v, "bilinear"))
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: resample '%s' is not none or bilinear", label, v);
  if (st == NBRDF_OK)
    f->resample = strcmp(v, "bilinear") ? NBRDF_RESAMPLE_NONE : NBRDF_RESAMPLE_BILINEAR;
  long q = 0, tiles = 0;
  if (st == NBRDF_OK) st = model_meta_int(r, "nbrdf.quantise", 0, 16, &q, err);
  if (st == NBRDF_OK) st = model_meta_int(r, "nbrdf.tiles", 1, 1000000, &tiles, err);
  f->quantise_bits = (int)q, f->tiles = (int)tiles;
  if (st == NBRDF_OK) st = meta_hex(r, "nbrdf.model_checksum", 0, f->model_checksum, err);
  if (st == NBRDF_OK) st = meta_hex(r, "nbrdf.base_decoder", 1, f->base_decoder, err);
  for (int id = 0; st == NBRDF_OK && id < NBRDF_BAKE_PARAM_COUNT; id++) {
    char key[64];
    snprintf(key, sizeof key, "nbrdf.inputs.%s", model_material_param_name(id));
    st = nn_st_metadata_require(r, key, &v, err);
    if (st == NBRDF_OK && !(f->inputs[id] = dup_text(v)))
      st = core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", label);
  }
  return st;
}

static nbrdf_status read_result(const nn_st_reader *r, nbrdf_fit *f, nbrdf_error *err) {
  const char *label = nn_st_label(r), *v = NULL;
  bake_fit_result *res = &f->r;
  bake_correction *c = &res->correction;
  long D = 0;
  nbrdf_status st = model_meta_int(r, "nbrdf.latent_dim", 1, NBRDF_LATENT_MAX_DIM, &D, err);
  if (st == NBRDF_OK) st = meta_size(r, "nbrdf.distinct", &res->distinct, err);
  if (st == NBRDF_OK) st = meta_size(r, "nbrdf.fitted", &res->fitted, err);
  if (st == NBRDF_OK) st = meta_size(r, "nbrdf.heldout", &res->heldout, err);
  if (st == NBRDF_OK)
    st = model_meta_double(r, "nbrdf.heldout_error", 0.0, 1e30, &res->heldout_error, err);
  if (st == NBRDF_OK)
    st = model_meta_double(r, "nbrdf.heldout_error_fast", 0.0, 1e30, &res->heldout_error_fast,
                           err);
  /* The energy guard's figures: absent from fit files made before it (no verdict then). */
  if (st == NBRDF_OK && nn_st_metadata_get(r, "nbrdf.albedo_tuples")) {
    st = meta_size(r, "nbrdf.albedo_tuples", &res->albedo_tuples, err);
    if (st == NBRDF_OK)
      st = model_meta_double(r, "nbrdf.albedo_max", 0.0, 1e30, &res->albedo_max, err);
    if (st == NBRDF_OK)
      st = model_meta_double(r, "nbrdf.albedo_max_fast", 0.0, 1e30, &res->albedo_max_fast, err);
  }
  if (st == NBRDF_OK) st = model_meta_double(r, "nbrdf.budget", 0.0, 1e30, &res->budget, err);
  if (st == NBRDF_OK) st = nn_st_metadata_require(r, "nbrdf.attribute", &v, err);
  if (st == NBRDF_OK) snprintf(res->attribute, sizeof res->attribute, "%s", v);
  const nn_st_tensor *tt = st == NBRDF_OK ? nn_st_find(r, "correction.tuples") : NULL;
  if (st == NBRDF_OK && (!tt || tt->ndim != 2 || tt->shape[0] < 1))
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: no tensor 'correction.tuples' [n, %d]", label,
                     NBRDF_BAKE_PARAM_COUNT);
  if (st != NBRDF_OK) return st;
  c->latent_dim = (int)D;
  c->n = (size_t)tt->shape[0];
  const int64_t P = NBRDF_BAKE_PARAM_COUNT, one = 1;
  const int64_t tuples_shape[2] = {(int64_t)c->n, P}, delta_shape[2] = {(int64_t)c->n, D};
  c->tuples = malloc(sizeof *c->tuples * c->n);
  c->delta = malloc(sizeof *c->delta * c->n * (size_t)D);
  if (!c->tuples || !c->delta) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", label);
  st = nn_st_expect_copy(r, "correction.tuples", 2, tuples_shape, c->tuples[0].p, err);
  if (st == NBRDF_OK) st = nn_st_expect_copy(r, "correction.delta", 2, delta_shape, c->delta, err);
  if (st == NBRDF_OK) st = nn_st_expect_copy(r, "correction.lo", 1, &P, c->lo, err);
  if (st == NBRDF_OK) st = nn_st_expect_copy(r, "correction.hi", 1, &P, c->hi, err);
  if (st == NBRDF_OK) st = nn_st_expect_copy(r, "correction.radius", 1, &one, &c->radius, err);
  const int specialised = f->accuracy >= NBRDF_BAKE_SPECIALISED;
  if (st == NBRDF_OK && specialised) st = read_decoder(r, "decoder/", &c->decoder, err);
  if (st == NBRDF_OK && f->accuracy == NBRDF_BAKE_COMPACT) {
    bake_compact *k = &res->compact;
    long K = 0;
    st = model_meta_int(r, "compact.dim", 1, BAKE_COMPACT_MAX_DIM, &K, err);
    if (st == NBRDF_OK) st = model_meta_double(r, "compact.kept", 0.0, 1.0, &k->kept, err);
    if (st == NBRDF_OK)
      st = model_meta_double(r, "compact.loss_truth", -1e30, 1e30, &k->loss_truth, err);
    if (st == NBRDF_OK)
      st = model_meta_double(r, "compact.loss_teacher", -1e30, 1e30, &k->loss_teacher, err);
    if (st != NBRDF_OK) return st;
    k->dim = (int)K, k->work_dim = (int)D;
    const int64_t basis_shape[2] = {D, K}, project_shape[2] = {K, D}, Dl = D;
    k->mean = malloc(sizeof(float) * (size_t)D);
    k->basis = malloc(sizeof(float) * (size_t)(D * K));
    k->project = malloc(sizeof(float) * (size_t)(D * K));
    if (!k->mean || !k->basis || !k->project)
      return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", label);
    st = nn_st_expect_copy(r, "compact.mean", 1, &Dl, k->mean, err);
    if (st == NBRDF_OK) st = nn_st_expect_copy(r, "compact.basis", 2, basis_shape, k->basis, err);
    if (st == NBRDF_OK)
      st = nn_st_expect_copy(r, "compact.project", 2, project_shape, k->project, err);
    if (st == NBRDF_OK) st = read_decoder(r, "student/", &k->student, err);
  }
  return st;
}

nbrdf_status bake_fit_file_read(const char *path, nbrdf_fit *f, nbrdf_error *err) {
  memset(f, 0, sizeof *f);
  nn_st_reader *r = NULL;
  nbrdf_status st = nn_st_open(path, &r, err);
  const char *v = NULL;
  if (st == NBRDF_OK) {
    v = nn_st_metadata_get(r, "nbrdf.format");
    if (!v || strcmp(v, BAKE_FIT_FORMAT))
      st = core_fail(err, NBRDF_ERR_FORMAT, "%s: not a fit file (nbrdf.format is '%s', not '%s')",
                     path, v ? v : "absent", BAKE_FIT_FORMAT);
  }
  if (st == NBRDF_OK) {
    v = nn_st_metadata_get(r, "nbrdf.version");
    if (!v || strcmp(v, BAKE_FIT_VERSION))
      st = core_fail(err, NBRDF_ERR_FORMAT, "%s: fit file version '%s'; this nbrdf reads '%s'",
                     path, v ? v : "absent", BAKE_FIT_VERSION);
  }
  if (st == NBRDF_OK) st = read_options(r, f, err);
  if (st == NBRDF_OK) st = read_result(r, f, err);
  if (st == NBRDF_OK) st = bake_fit_decoder_checksum(&f->r, f->decoder_checksum, err);
  if (st == NBRDF_OK) {
    /* The stored checksum must be what the decoders serialise to: else the
     * textures would record another decoder than the file says. */
    v = nn_st_metadata_get(r, "nbrdf.decoder_checksum");
    if (!v || strcmp(v, f->decoder_checksum))
      st = core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: its decoder's checksum is %s, but the file records '%s'", path,
                     f->decoder_checksum[0] ? f->decoder_checksum : "(none)", v ? v : "");
  }
  if (st == NBRDF_OK) {
    snprintf(f->file_checksum, sizeof f->file_checksum, "%016" PRIx64, nn_st_checksum(r));
    if (!(f->path = dup_text(path))) st = core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  }
  nn_st_close(r);
  if (st != NBRDF_OK) bake_fit_release(f);
  return st;
}

void bake_fit_release(nbrdf_fit *f) {
  bake_fit_result_free(&f->r);
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    free(f->inputs[id]);
  free(f->path);
  memset(f, 0, sizeof *f);
}
