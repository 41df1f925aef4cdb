/* The texture's side of verify: one latent decoded into the lobe images of
 * docs/METRICS.md. The query directions are built once; latents decoded before
 * are served from a small cache, since a texture baked from constants or a
 * few painted values repeats the same latent in most texels. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "verify/verify_internal.h"

const double verify_theta_deg[VERIFY_N_THETA] = {0.0, 30.0, 60.0, 80.0, 85.0, 89.0};
/* Golden-angle steps: every image at another azimuth, none of them a symmetry of another. */
const double verify_phi_deg[VERIFY_N_THETA] = {0.0, 137.5, 275.0, 52.5, 190.0, 327.5};

/* Distinct latents kept: enough for the regions of a painted map. */
#define CACHE_MAX 32

struct verify_decoder {
  const nbrdf_model *model;
  int dim;
  size_t n;       /* queries: pixels inside the disk × images */
  float *wi, *wo; /* n × 3 */
  size_t *pixel;  /* n: index into the image set */
  double *cos_o;  /* n: cos θo of the pixel */
  float *latents; /* n × dim: the latent, repeated (the decoder takes one per query) */
  float *f;       /* n */
  float *keys;    /* CACHE_MAX × dim */
  double *images; /* CACHE_MAX × VERIFY_SET */
  size_t cached, distinct, queries;
};

void verify_decoder_free(verify_decoder *d) {
  if (!d) return;
  free(d->wi), free(d->wo), free(d->pixel), free(d->cos_o), free(d->latents), free(d->f);
  free(d->keys), free(d->images);
  free(d);
}

verify_decoder *verify_decoder_create(const nbrdf_model *model) {
  verify_decoder *d = calloc(1, sizeof *d);
  if (!d) return NULL;
  d->model = model;
  d->dim = nbrdf_model_latent_dim(model);
  const int res = NBRDF_LOBE_RES;
  size_t cap = lobe_pixels_inside(res) * VERIFY_N_THETA;
  d->wi = malloc(cap * 3 * sizeof(float));
  d->wo = malloc(cap * 3 * sizeof(float));
  d->pixel = malloc(cap * sizeof(size_t));
  d->cos_o = malloc(cap * sizeof(double));
  d->latents = malloc(cap * (size_t)d->dim * sizeof(float));
  d->f = malloc(cap * sizeof(float));
  d->keys = malloc((size_t)CACHE_MAX * (size_t)d->dim * sizeof(float));
  d->images = malloc((size_t)CACHE_MAX * VERIFY_SET * sizeof(double));
  if (!d->wi || !d->wo || !d->pixel || !d->cos_o || !d->latents || !d->f || !d->keys ||
      !d->images) {
    verify_decoder_free(d);
    return NULL;
  }
  for (int t = 0; t < VERIFY_N_THETA; t++) {
    double th = verify_theta_deg[t] * (M_PI / 180.0), phi = verify_phi_deg[t] * (M_PI / 180.0);
    double c = cos(phi), s = sin(phi);
    for (int p = 0; p < res * res; p++) {
      double wo[3];
      if (!lobe_pixel_wo(res, p / res, p % res, wo)) continue;
      float *i3 = d->wi + 3 * d->n, *o3 = d->wo + 3 * d->n;
      i3[0] = (float)(c * sin(th)), i3[1] = (float)(s * sin(th)), i3[2] = (float)cos(th);
      o3[0] = (float)(c * wo[0] - s * wo[1]), o3[1] = (float)(s * wo[0] + c * wo[1]);
      o3[2] = (float)wo[2];
      d->pixel[d->n] = (size_t)t * res * res + (size_t)p;
      d->cos_o[d->n] = wo[2];
      d->n++;
    }
  }
  return d;
}

size_t verify_decoder_distinct(const verify_decoder *d) { return d->distinct; }
size_t verify_decoder_queries(const verify_decoder *d) { return d->queries; }

nbrdf_status verify_decode(verify_decoder *d, const float *latent, double *images, int *finite,
                           nbrdf_error *err) {
  const size_t D = (size_t)d->dim;
  *finite = 1;
  for (size_t k = 0; k < D; k++)
    if (!isfinite(latent[k])) {
      *finite = 0;
      return NBRDF_OK;
    }
  for (size_t c = 0; c < d->cached; c++)
    if (!memcmp(d->keys + c * D, latent, D * sizeof(float))) {
      memcpy(images, d->images + c * VERIFY_SET, VERIFY_SET * sizeof(double));
      return NBRDF_OK;
    }
  for (size_t q = 0; q < d->n; q++)
    memcpy(d->latents + q * D, latent, D * sizeof(float));
  nbrdf_status st = nbrdf_model_decode(d->model, d->n, 1, d->latents, d->wi, d->wo, d->f, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "verify: decode: ");
    return st;
  }
  d->distinct++;
  d->queries += d->n;
  memset(images, 0, VERIFY_SET * sizeof(double));
  for (size_t q = 0; q < d->n; q++) {
    if (!isfinite(d->f[q])) {
      *finite = 0;
      return NBRDF_OK;
    }
    images[d->pixel[q]] = (double)d->f[q] * d->cos_o[q];
  }
  if (d->cached < CACHE_MAX) {
    memcpy(d->keys + d->cached * D, latent, D * sizeof(float));
    memcpy(d->images + d->cached * VERIFY_SET, images, VERIFY_SET * sizeof(double));
    d->cached++;
  }
  return NBRDF_OK;
}
