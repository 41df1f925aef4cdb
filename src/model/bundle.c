#include "model/bundle.h"

#include <cjson/cJSON.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "model/bundle_json.h"
#include "model/files.h"

const char *const model_bundle_files[4] = {"decoder.safetensors", "layering.safetensors",
                                           "sampler.safetensors", "base_tables.safetensors"};

#define BUNDLE_PATH_MAX 4096

static nbrdf_status join(char *buf, const char *dir, const char *file, nbrdf_error *err) {
  int n = snprintf(buf, BUNDLE_PATH_MAX, "%s/%s", dir, file);
  if (n < 0 || n >= BUNDLE_PATH_MAX)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: path too long", dir);
  return NBRDF_OK;
}

void nbrdf_model_destroy(nbrdf_model *m) {
  if (!m) return;
  /* A bundle some derived model still holds lives on until the last one goes. */
  if (atomic_fetch_sub(&m->extra_refs, 1) > 0) return;
  if (m->parent) {
    if (m->own_decoder) model_decoder_destroy(m->decoder);
    free(m->decoder_bytes);
    nbrdf_model *parent = m->parent;
    free(m);
    nbrdf_model_destroy(parent);
    return;
  }
  model_decoder_destroy(m->decoder);
  model_layering_destroy(m->layering);
  model_sampler_destroy(m->sampler);
  model_base_table_free(&m->tables[0]);
  model_base_table_free(&m->tables[1]);
  free(m->files_text);
  free(m);
}

static nbrdf_status read_tables(const nn_st_reader *r, nbrdf_model *m, nbrdf_error *err) {
  const char *label = nn_st_label(r), *format = nn_st_metadata_get(r, "nbrdf.format");
  if (!format || strcmp(format, "nbrdf-base-tables") != 0)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: metadata nbrdf.format is not \"nbrdf-base-tables\"", label);
  long version, dim;
  nbrdf_status st = model_meta_int(r, "nbrdf.version", 1, 1, &version, err);
  if (st == NBRDF_OK) st = model_meta_int(r, "nbrdf.latent_dim", 1, 4096, &dim, err);
  if (st == NBRDF_OK && dim != m->latent_dim)
    st = core_fail(err, NBRDF_ERR_MISMATCH, "%s: latent dimension %ld, the bundle's is %d", label,
                   dim, m->latent_dim);
  if (st == NBRDF_OK)
    st = model_base_table_read(r, MODEL_TABLE_DIELECTRIC, m->latent_dim, &m->tables[0], err);
  if (st == NBRDF_OK)
    st = model_base_table_read(r, MODEL_TABLE_CONDUCTOR, m->latent_dim, &m->tables[1], err);
  if (st == NBRDF_OK && nn_st_tensor_count(r) != 6)
    st = core_fail(err, NBRDF_ERR_MISMATCH, "%s: %zu tensors, expected the 6 of two tables", label,
                   nn_st_tensor_count(r));
  return st;
}

/* Reads file i of model_bundle_files into the model; `hash` continues the checksum. */
static nbrdf_status load_part(const char *dir, int i, nbrdf_model *m, uint64_t *hash,
                              nbrdf_error *err) {
  char path[BUNDLE_PATH_MAX];
  nbrdf_status st = join(path, dir, model_bundle_files[i], err);
  char *bytes = NULL;
  size_t size = 0;
  if (st == NBRDF_OK) st = model_read_file(path, NBRDF_ST_FILE_MAX, &bytes, &size, err);
  if (st != NBRDF_OK) return st;
  *hash = nn_st_fnv1a64(*hash, bytes, size);
  nn_st_reader *r = NULL;
  st = nn_st_open_memory(bytes, size, path, &r, err);
  free(bytes);
  if (st != NBRDF_OK) return st;
  int dim = 0;
  const char *what = NULL;
  switch (i) {
  case 0:
    st = model_decoder_read(r, &m->decoder, err);
    if (st == NBRDF_OK) dim = m->decoder->cfg.latent_dim, what = "decoder";
    break;
  case 1:
    st = model_layering_read(r, &m->layering, err);
    if (st == NBRDF_OK) dim = m->layering->latent_dim, what = "layering network";
    break;
  case 2:
    st = model_sampler_read(r, &m->sampler, err);
    if (st == NBRDF_OK) dim = m->sampler->latent_dim, what = "sampling network";
    break;
  default:
    st = read_tables(r, m, err);
    break;
  }
  if (st == NBRDF_OK && what && dim != m->latent_dim)
    st =
        core_fail(err, NBRDF_ERR_MISMATCH, "%s: the %s has latent dimension %d, model.json says %d",
                  path, what, dim, m->latent_dim);
  nn_st_close(r);
  return st;
}

/* The paths nbrdf_model_files reports, in one allocation. The card is not read, but it is
 * one of the bundle's files: an output over it would damage the bundle all the same. */
static nbrdf_status remember_files(const char *dir, nbrdf_model *m, nbrdf_error *err) {
  const char *names[MODEL_FILES] = {"model.json",          model_bundle_files[0],
                                    model_bundle_files[1], model_bundle_files[2],
                                    model_bundle_files[3], "MODEL_CARD.md"};
  size_t total = 0;
  for (int i = 0; i < MODEL_FILES; i++)
    total += strlen(dir) + strlen(names[i]) + 2;
  char *p = m->files_text = malloc(total);
  if (!p) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", dir);
  for (int i = 0; i < MODEL_FILES; i++) {
    m->files[i] = p;
    p += sprintf(p, "%s/%s", dir, names[i]) + 1;
  }
  return NBRDF_OK;
}

nbrdf_status nbrdf_model_load(const char *dir, nbrdf_model **out, nbrdf_error *err) {
  if (!dir || !out) return core_fail(err, NBRDF_ERR_ARGUMENT, "model load: NULL argument");
  nbrdf_model *m = calloc(1, sizeof *m);
  if (!m) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", dir);
  char expected_checksum[17] = "";
  nbrdf_status st = model_bundle_read_json(dir, m, expected_checksum, err);
  uint64_t hash = NBRDF_ST_FNV1A64_INIT;
  for (int i = 0; i < 4 && st == NBRDF_OK; i++)
    st = load_part(dir, i, m, &hash, err);
  if (st == NBRDF_OK) {
    m->checksum = hash;
    snprintf(m->checksum_hex, sizeof m->checksum_hex, "%016" PRIx64, hash);
    if (strcmp(expected_checksum, m->checksum_hex) != 0)
      st = core_fail(err, NBRDF_ERR_MISMATCH,
                     "%s/model.json: checksum %s does not match the weight files' %s (a file was "
                     "damaged, or replaced without reassembling the bundle with `nbrdf train "
                     "bundle`)",
                     dir, expected_checksum, m->checksum_hex);
  }
  if (st == NBRDF_OK) st = model_bundle_check_json(dir, m, err);
  if (st == NBRDF_OK) st = remember_files(dir, m, err);
  if (st != NBRDF_OK) {
    nbrdf_model_destroy(m);
    return st;
  }
  *out = m;
  return NBRDF_OK;
}

const char *nbrdf_model_name(const nbrdf_model *m) { return m->name; }
const char *nbrdf_model_checksum(const nbrdf_model *m) { return m->checksum_hex; }
int nbrdf_model_latent_dim(const nbrdf_model *m) { return m->latent_dim; }
int nbrdf_model_is_trained(const nbrdf_model *m) { return m->trained; }
int nbrdf_model_files(const nbrdf_model *m, const char *const **paths) {
  *paths = m->files;
  return MODEL_FILES;
}
int64_t nbrdf_model_decoder_macs(const nbrdf_model *m) { return model_decoder_macs(m->decoder); }
int64_t nbrdf_model_layering_macs(const nbrdf_model *m) {
  return nn_spec_macs(nn_get_spec(m->layering->nn));
}

void nbrdf_model_base_grid(const nbrdf_model *m, nbrdf_base_kind kind, int *n0, const float **axis0,
                           int *n1, const float **axis1) {
  const model_base_table *t = &m->tables[kind == NBRDF_BASE_CONDUCTOR];
  *n0 = t->n[0], *axis0 = t->axis[0];
  *n1 = t->n[1], *axis1 = t->axis[1];
}

/* ------------------------------------------------------------------ saving */

static nbrdf_status check_parts(const model_bundle_parts *p, nbrdf_error *err) {
  int dim = p->decoder->cfg.latent_dim;
  if (p->layering->latent_dim != dim || p->sampler->latent_dim != dim || p->tables[0]->dim != dim ||
      p->tables[1]->dim != dim)
    return core_fail(err, NBRDF_ERR_MISMATCH,
                     "bundle: latent dimensions disagree (decoder %d, layering %d, sampler %d, "
                     "tables %d and %d)",
                     dim, p->layering->latent_dim, p->sampler->latent_dim, p->tables[0]->dim,
                     p->tables[1]->dim);
  if (p->tables[0]->kind != MODEL_TABLE_DIELECTRIC || p->tables[1]->kind != MODEL_TABLE_CONDUCTOR)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "bundle: tables must be (dielectric, conductor)");
  if (!p->name || !*p->name || strlen(p->name) >= sizeof(((nbrdf_model *)0)->name))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "bundle: the name must have 1..63 characters");
  return NBRDF_OK;
}

nbrdf_status model_tables_save(const model_base_table *const tables[2], const char *path,
                               nbrdf_error *err) {
  nn_st_writer *w = NULL;
  char dim[16];
  snprintf(dim, sizeof dim, "%d", tables[0]->dim);
  nbrdf_status st = nn_st_writer_create(&w, err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.format", "nbrdf-base-tables", err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.version", "1", err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.latent_dim", dim, err);
  if (st == NBRDF_OK) st = model_base_table_write(tables[0], w, err);
  if (st == NBRDF_OK) st = model_base_table_write(tables[1], w, err);
  if (st == NBRDF_OK) st = nn_st_writer_save(w, path, NULL, err);
  nn_st_writer_destroy(w);
  return st;
}

nbrdf_status model_bundle_save(const char *dir, const model_bundle_parts *p, uint64_t *checksum,
                               nbrdf_error *err) {
  nbrdf_status st = check_parts(p, err);
  if (st != NBRDF_OK) return st;
  st = model_make_dirs(dir, err);
  if (st != NBRDF_OK) return st;
  char path[BUNDLE_PATH_MAX];
  uint64_t hash = NBRDF_ST_FNV1A64_INIT;
  for (int i = 0; i < 4 && st == NBRDF_OK; i++) {
    st = join(path, dir, model_bundle_files[i], err);
    if (st != NBRDF_OK) break;
    if (i == 0) st = model_decoder_save(p->decoder, path, NULL, err);
    if (i == 1) st = model_layering_save(p->layering, path, NULL, err);
    if (i == 2) st = model_sampler_save(p->sampler, path, NULL, err);
    if (i == 3) st = model_tables_save(p->tables, path, err);
    /* Hash what is on disk, so the value is the one load computes. */
    char *bytes = NULL;
    size_t size = 0;
    if (st == NBRDF_OK) st = model_read_file(path, NBRDF_ST_FILE_MAX, &bytes, &size, err);
    if (st == NBRDF_OK) hash = nn_st_fnv1a64(hash, bytes, size);
    free(bytes);
  }
  if (st == NBRDF_OK) st = model_bundle_write_json(dir, p, hash, err);
  if (st == NBRDF_OK) st = model_bundle_write_card(dir, p, hash, err);
  if (st == NBRDF_OK && checksum) *checksum = hash;
  return st;
}
