/* nbrdf_render_lobes: the lobe images of one texel, decoded, beside its
 * ground truth (render.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "texture/latent_fetch.h"
#include "lobe/lobe.h"
#include "lobe/lobe_png.h"
#include "nbrdf/render.h"

typedef struct decode_fn_user {
  const nbrdf_model *model;
  const float *latent; /* one colour channel's latents */
} decode_fn_user;

static nbrdf_status decode_fn(void *user, size_t n, const nbrdf_query *q, double *f,
                              nbrdf_error *err) {
  const decode_fn_user *u = user;
  int D = nbrdf_model_latent_dim(u->model);
  float *lat = malloc(sizeof(float) * n * D), *wi = malloc(sizeof(float) * n * 3);
  float *wo = malloc(sizeof(float) * n * 3), *ff = malloc(sizeof(float) * n);
  nbrdf_status st = NBRDF_OK;
  if (!lat || !wi || !wo || !ff) st = core_fail(err, NBRDF_ERR_MEMORY, "lobes: out of memory");
  for (size_t k = 0; st == NBRDF_OK && k < n; k++) {
    memcpy(lat + k * D, u->latent, sizeof(float) * D);
    for (int a = 0; a < 3; a++)
      wi[3 * k + a] = (float)q[k].wi[a], wo[3 * k + a] = (float)q[k].wo[a];
  }
  if (st == NBRDF_OK) st = nbrdf_model_decode(u->model, n, 1, lat, wi, wo, ff, err);
  for (size_t k = 0; st == NBRDF_OK && k < n; k++)
    f[k] = ff[k];
  free(lat), free(wi), free(wo), free(ff);
  return st;
}

nbrdf_status nbrdf_render_lobes(const nbrdf_model *model, const char *latent_path, int x, int y,
                                int level, const nbrdf_brdf *const *reference,
                                int reference_channels, int spp, uint64_t seed,
                                const char *png_path, double *lobe_error, nbrdf_error *err) {
  if (lobe_error) *lobe_error = NAN;
  texture_latent_image *tex = NULL;
  nbrdf_model *decoding = NULL; /* with the texture's own decoder, if it has one */
  nbrdf_status st = texture_latent_image_load_model(latent_path, model, &tex, &decoding, err);
  if (st != NBRDF_OK) return st;
  int colours = texture_latent_colours(&tex->layout);
  if (level < 0 || level >= tex->levels)
    st = core_fail(err, NBRDF_ERR_ARGUMENT, "%s has %d mip level%s (0..%d); there is no level %d",
                   latent_path, tex->levels, tex->levels == 1 ? "" : "s", tex->levels - 1, level);
  else if (x < 0 || y < 0 || x >= tex->width[level] || y >= tex->height[level])
    st = core_fail(err, NBRDF_ERR_ARGUMENT, "%s: texel (%d, %d) is outside level %d (%d x %d)",
                   latent_path, x, y, level, tex->width[level], tex->height[level]);
  else if (reference && reference_channels != 1 && reference_channels != colours)
    st = core_fail(err, NBRDF_ERR_MISMATCH, "%d reference BRDFs for a texture of %d colours",
                   reference_channels, colours);
  else if (reference && spp < 1)
    st = core_fail(err, NBRDF_ERR_ARGUMENT, "lobes: %d samples per pixel", spp);
  size_t per = (size_t)NBRDF_LOBE_RES * NBRDF_LOBE_RES * NBRDF_LOBE_N_THETA;
  double *dec = NULL, *ref = NULL;
  if (st == NBRDF_OK) {
    dec = malloc(sizeof(double) * per * colours);
    ref = reference ? malloc(sizeof(double) * per * colours) : NULL;
    if (!dec || (reference && !ref)) st = core_fail(err, NBRDF_ERR_MEMORY, "lobes: out of memory");
  }
  const float *texel = st == NBRDF_OK ? tex->data[level] + ((size_t)y * tex->width[level] + x) *
                                                               (size_t)tex->channels
                                      : NULL;
  for (int c = 0; st == NBRDF_OK && c < colours; c++) {
    decode_fn_user u = {decoding, texel + (size_t)c * texture_latent_block(&tex->layout)};
    st = lobe_images(decode_fn, &u, NBRDF_LOBE_RES, NBRDF_LOBE_N_THETA, lobe_theta_deg,
                     dec + c * per, err);
    if (st == NBRDF_OK && reference) {
      lobe_brdf lb = {reference[reference_channels == 1 ? 0 : c], NBRDF_EVAL_OPTIONS_DEFAULT};
      lb.options.spp = spp, lb.options.seed = seed + (uint64_t)c;
      st = lobe_images(lobe_brdf_fn, &lb, NBRDF_LOBE_RES, NBRDF_LOBE_N_THETA, lobe_theta_deg,
                       ref + c * per, err);
    }
  }
  if (st == NBRDF_OK)
    st = lobe_write_png(png_path, NBRDF_LOBE_RES, NBRDF_LOBE_N_THETA * colours,
                        reference ? ref : dec, reference ? dec : NULL, 2, err);
  if (st == NBRDF_OK && reference && lobe_error)
    *lobe_error = lobe_l1_error(per * colours, ref, dec);
  free(dec), free(ref);
  texture_latent_image_free(tex);
  nbrdf_model_destroy(decoding);
  return st;
}
