/* Models with a decoder of their own (include/nbrdf/model.h, "own decoders"):
 * a derived nbrdf_model shares the layering and sampling networks, tables and
 * identity of a loaded bundle, holding a reference to it, and brings its own
 * decoder, read from safetensors bytes that it keeps (a bake embeds them in
 * the texture, so what a renderer decodes with is exactly what was used). */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "model/bundle.h"
#include "model/files.h"

/* Parses and checks the decoder bytes against the bundle. */
static nbrdf_status read_decoder(const nbrdf_model *root, const void *bytes, size_t size,
                                 const char *label, model_decoder **out, nbrdf_error *err) {
  if (size > NBRDF_DECODER_BYTES_MAX)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s: %zu bytes, more than the %zu MiB a decoder may have", label, size,
                     NBRDF_DECODER_BYTES_MAX >> 20);
  nn_st_reader *r = NULL;
  nbrdf_status st = nn_st_open_memory(bytes, size, label, &r, err);
  if (st == NBRDF_OK) st = model_decoder_read(r, out, err);
  nn_st_close(r);
  if (st != NBRDF_OK) return st;
  /* A compact texture's decoder (docs/BAKE.md) reads fewer latents than the
   * bundle's networks write; never more. */
  if ((*out)->cfg.latent_dim > root->latent_dim) {
    int dim = (*out)->cfg.latent_dim;
    model_decoder_destroy(*out);
    *out = NULL;
    return core_fail(err, NBRDF_ERR_MISMATCH,
                     "%s: the decoder has latent dimension %d, more than the bundle '%s''s %d",
                     label, dim, root->name, root->latent_dim);
  }
  return NBRDF_OK;
}

nbrdf_status model_derive(const nbrdf_model *base, const void *bytes, size_t size,
                          const char *label, nbrdf_model **out, nbrdf_error *err) {
  if (!base || !out || (!bytes && size))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "model with decoder: NULL argument");
  *out = NULL;
  if (!label) label = "decoder";
  /* The bundle's parts always come from the loaded bundle, never from another
   * derived model, so chains stay one link long. */
  nbrdf_model *root = base->parent ? base->parent : (nbrdf_model *)base;
  if (!bytes && base->own_decoder) {
    /* A new reference to a model with its own decoder keeps that decoder. */
    bytes = base->decoder_bytes;
    size = base->decoder_size;
  }
  model_decoder *dec = NULL;
  nbrdf_status st = bytes ? read_decoder(root, bytes, size, label, &dec, err) : NBRDF_OK;
  if (st != NBRDF_OK) return st;
  nbrdf_model *m = calloc(1, sizeof *m);
  unsigned char *copy = bytes ? malloc(size ? size : 1) : NULL;
  if (!m || (bytes && !copy)) {
    free(m);
    free(copy);
    model_decoder_destroy(dec);
    return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", label);
  }
  memcpy(m->name, root->name, sizeof m->name);
  m->trained = root->trained;
  m->latent_dim = dec ? dec->cfg.latent_dim : root->latent_dim;
  m->checksum = root->checksum;
  memcpy(m->checksum_hex, root->checksum_hex, sizeof m->checksum_hex);
  memcpy(m->reads, root->reads, sizeof m->reads);
  m->n_reads = root->n_reads;
  memcpy(m->audit_slope, root->audit_slope, sizeof m->audit_slope);
  m->has_audit_slopes = root->has_audit_slopes;
  m->audit_slopes_both_ways = root->audit_slopes_both_ways;
  m->layering = root->layering;
  m->sampler = root->sampler;
  m->tables[0] = root->tables[0];
  m->tables[1] = root->tables[1];
  memcpy(m->files, root->files, sizeof m->files);
  m->parent = root;
  atomic_init(&m->extra_refs, 0);
  atomic_fetch_add(&root->extra_refs, 1);
  if (dec) {
    memcpy(copy, bytes, size);
    m->decoder = dec;
    m->own_decoder = 1;
    m->decoder_bytes = copy;
    m->decoder_size = size;
    snprintf(m->decoder_checksum_hex, sizeof m->decoder_checksum_hex, "%016" PRIx64,
             nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, bytes, size));
  } else {
    m->decoder = root->decoder;
  }
  *out = m;
  return NBRDF_OK;
}

nbrdf_status nbrdf_model_with_decoder(const nbrdf_model *base, const void *bytes, size_t size,
                                      const char *label, nbrdf_model **out, nbrdf_error *err) {
  if (!bytes)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: no decoder bytes", label ? label : "decoder");
  return model_derive(base, bytes, size, label, out, err);
}

nbrdf_status nbrdf_model_with_decoder_file(const nbrdf_model *base, const char *path,
                                           nbrdf_model **out, nbrdf_error *err) {
  if (!path) return core_fail(err, NBRDF_ERR_ARGUMENT, "model with decoder: NULL path");
  char *bytes = NULL;
  size_t size = 0;
  /* One byte over the limit is enough to tell "too large" from "fits". */
  nbrdf_status st = model_read_file(path, NBRDF_DECODER_BYTES_MAX + 1, &bytes, &size, err);
  if (st == NBRDF_OK) st = nbrdf_model_with_decoder(base, bytes, size, path, out, err);
  free(bytes);
  return st;
}

nbrdf_status model_with_decoder_net(const nbrdf_model *base, const model_decoder *dec,
                                    nbrdf_model **out, nbrdf_error *err) {
  void *bytes = NULL;
  size_t size = 0;
  nbrdf_status st = model_decoder_serialize(dec, &bytes, &size, err);
  if (st == NBRDF_OK) st = model_derive(base, bytes, size, "decoder", out, err);
  free(bytes);
  return st;
}

void nbrdf_model_own_decoder(const nbrdf_model *m, nbrdf_decoder_info *info) {
  memset(info, 0, sizeof *info);
  if (!m || !m->own_decoder) return;
  info->own = 1;
  info->size = m->decoder_size;
  memcpy(info->checksum, m->decoder_checksum_hex, sizeof info->checksum);
  info->bytes = m->decoder_bytes;
}
