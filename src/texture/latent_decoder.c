/* The decoder a latent texture is decoded with: its own (format version 2)
 * or the bundle's (include/nbrdf/model.h, "own decoders"). */
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "model/bundle.h"
#include "texture/latent_exr.h"

nbrdf_status texture_latent_reader_model(const texture_latent_reader *r, const nbrdf_model *bundle,
                                         nbrdf_model **out, nbrdf_error *err) {
  const texture_latent_info *info = texture_latent_reader_info(r);
  const char *path = texture_latent_reader_path(r);
  const char *name = nbrdf_model_name(bundle), *sum = nbrdf_model_checksum(bundle);
  /* A texture of an earlier bundle that shares this one's decoder (model.json's
   * "reads_textures_of") decodes here exactly as with its own bundle. */
  for (int k = 0; k < bundle->n_reads; k++)
    if (!strcmp(info->model_checksum, bundle->reads[k].checksum_hex) &&
        !strcmp(info->model_name, bundle->reads[k].name))
      name = bundle->reads[k].name, sum = bundle->reads[k].checksum_hex;
  nbrdf_status st = texture_latent_check_model(info, path, name, sum, err);
  if (st != NBRDF_OK) return st;
  size_t size = 0;
  const void *bytes = texture_latent_reader_decoder(r, &size);
  /* A texture with its own decoder may be compact (fewer latents than the
   * bundle's): its decoder, not the bundle, says how many. */
  if (!bytes && info->layout.latent_dim != nbrdf_model_latent_dim(bundle))
    return core_fail(err, NBRDF_ERR_MISMATCH, "%s: latent dimension %d, the model's is %d", path,
                     info->layout.latent_dim, nbrdf_model_latent_dim(bundle));
  if (!bytes) return model_derive(bundle, NULL, 0, path, out, err);
  /* Every message about the bytes names the texture they came from. */
  char label[4200];
  snprintf(label, sizeof label, "%s: embedded decoder (%s)", path, NBRDF_ATTR_DECODER);
  st = model_derive(bundle, bytes, size, label, out, err);
  if (st == NBRDF_OK && nbrdf_model_latent_dim(*out) != info->layout.latent_dim) {
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: decodes latents of %d floats, the texture's have %d",
                    label, nbrdf_model_latent_dim(*out), info->layout.latent_dim);
    nbrdf_model_destroy(*out);
    *out = NULL;
  }
  if (st == NBRDF_OK || st == NBRDF_ERR_MEMORY) return st;
  if (err) err->status = NBRDF_ERR_FORMAT;
  return NBRDF_ERR_FORMAT;
}

nbrdf_status texture_latent_reader_check_decoder(const texture_latent_reader *r, char *about,
                                                 size_t about_size, nbrdf_error *err) {
  if (about && about_size) about[0] = '\0';
  size_t size = 0;
  const void *bytes = texture_latent_reader_decoder(r, &size);
  if (!bytes) return NBRDF_OK;
  const char *path = texture_latent_reader_path(r);
  char label[4200];
  snprintf(label, sizeof label, "%s: embedded decoder (%s)", path, NBRDF_ATTR_DECODER);
  nn_st_reader *st_r = NULL;
  model_decoder *dec = NULL;
  nbrdf_status st = nn_st_open_memory(bytes, size, label, &st_r, err);
  if (st == NBRDF_OK) st = model_decoder_read(st_r, &dec, err);
  nn_st_close(st_r);
  int dim = texture_latent_reader_info(r)->layout.latent_dim;
  if (st == NBRDF_OK && dec->cfg.latent_dim != dim)
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: decodes latents of %d floats, the texture's have %d",
                   label, dec->cfg.latent_dim, dim);
  if (st == NBRDF_OK && about && about_size)
    snprintf(about, about_size, "%s, %s output, %lld multiply-adds per query", dec->cfg.preset,
             model_output_name(dec->cfg.output), (long long)model_decoder_macs(dec));
  model_decoder_destroy(dec);
  if (st == NBRDF_OK || st == NBRDF_ERR_MEMORY) return st;
  if (err) err->status = NBRDF_ERR_FORMAT;
  return NBRDF_ERR_FORMAT;
}

nbrdf_status nbrdf_model_for_texture(const nbrdf_model *bundle, const char *texture_path,
                                     nbrdf_model **out, nbrdf_error *err) {
  if (!bundle || !texture_path || !out)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "model for texture: NULL argument");
  *out = NULL;
  texture_latent_reader *r = NULL;
  nbrdf_status st = texture_latent_reader_open(&r, texture_path, err);
  if (st == NBRDF_OK) st = texture_latent_reader_model(r, bundle, out, err);
  texture_latent_reader_close(r);
  return st;
}

nbrdf_status nbrdf_texture_own_decoder(const char *texture_path, nbrdf_decoder_info *info,
                                       nbrdf_error *err) {
  if (!texture_path || !info)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "texture own decoder: NULL argument");
  memset(info, 0, sizeof *info);
  texture_latent_reader *r = NULL;
  nbrdf_status st = texture_latent_reader_open(&r, texture_path, err);
  if (st != NBRDF_OK) return st;
  const texture_latent_info *in = texture_latent_reader_info(r);
  if (in->decoder_size) {
    info->own = 1;
    info->size = in->decoder_size;
    snprintf(info->checksum, sizeof info->checksum, "%s", in->decoder_checksum);
  }
  texture_latent_reader_close(r);
  return NBRDF_OK;
}
