#include "bake/bake_heldout.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_truth.h"
#include "core/error.h"
#include "core/sort.h"
#include "model/bundle.h"

static double lobe_error(size_t n, const double *ref, const double *approx) {
  double num = 0.0, den = 0.0;
  for (size_t i = 0; i < n; i++)
    num += fabs(approx[i] - ref[i]), den += fabs(ref[i]);
  return den > 0.0 ? num / den : (num > 0.0 ? INFINITY : 0.0);
}

static double median(double *v, size_t n) {
  if (n == 0) return 0.0;
  core_sort_doubles(v, n);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Decodes the lobe images of `latent` with `dec` into img (f cos θo), image
 * i asked with ωi and ωo rotated by phi[i] about the normal (the truth's
 * pixel is the same: the layered BRDF is isotropic). */
static nbrdf_status decode_lobes(const model_decoder *dec, model_runner *run, const float *latent,
                                 int res, const double *phi, float *lat, float *wi, float *wo,
                                 float *f, double *img, nbrdf_error *err) {
  const int D = dec->cfg.latent_dim;
  size_t px = (size_t)res * res, q = 0;
  for (int i = 0; i < BAKE_LOBE_N_THETA; i++) {
    double th = bake_lobe_theta_deg[i] * (M_PI / 180.0);
    double c = cos(phi[i]), s = sin(phi[i]);
    for (int r = 0; r < res; r++)
      for (int col = 0; col < res; col++) {
        float w[3];
        if (!bake_lobe_pixel_wo(res, r, col, w)) continue;
        wo[3 * q] = (float)(c * w[0] - s * w[1]);
        wo[3 * q + 1] = (float)(s * w[0] + c * w[1]);
        wo[3 * q + 2] = w[2];
        wi[3 * q] = (float)(c * sin(th)), wi[3 * q + 1] = (float)(s * sin(th));
        wi[3 * q + 2] = (float)cos(th);
        memcpy(lat + q * D, latent, sizeof(float) * D);
        q++;
      }
  }
  nbrdf_status st = model_decoder_eval(dec, run, q, 1, lat, wi, wo, f, err);
  if (st != NBRDF_OK) return st;
  q = 0;
  for (int i = 0; i < BAKE_LOBE_N_THETA; i++)
    for (int r = 0; r < res; r++)
      for (int col = 0; col < res; col++) {
        float w[3];
        double *p = img + i * px + (size_t)r * res + col;
        *p = 0.0;
        if (!bake_lobe_pixel_wo(res, r, col, w)) continue;
        *p = (double)f[q++] * w[2];
      }
  return NBRDF_OK;
}

nbrdf_status bake_heldout_error(const nbrdf_model *model, const bake_correction *c,
                                const bake_compact *compact, const bake_tuple *t, size_t n,
                                const double *images, int res, uint64_t seed, double *fitted,
                                double *fast, double *per_tuple, nbrdf_error *err) {
  const int D = nbrdf_model_latent_dim(model);
  size_t px = (size_t)res * res, all = BAKE_LOBE_N_THETA * px;
  float *net = malloc(sizeof(float) * n * (D + 2) + 1);
  float *lat = malloc(sizeof(float) * all * D), *dirs = malloc(sizeof(float) * all * 7);
  double *img = malloc(sizeof(double) * all), *errs = malloc(sizeof(double) * 2 * n + 1);
  model_runner run_u = {0}, run_s = {0};
  nbrdf_status st = NBRDF_OK;
  if (!net || !lat || !dirs || !img || !errs)
    st = core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for the held-out error");
  if (st == NBRDF_OK) st = bake_tuples_evaluate(model, t, NULL, n, net, err);
  const model_decoder *spec = compact ? compact->student : bake_correction_decoder(c, model);
  float coords[BAKE_COMPACT_MAX_DIM];
  if (st == NBRDF_OK)
    st = model_runner_create(model->decoder->nn, 4096, NBRDF_NN_INFER, &run_u, err);
  if (st == NBRDF_OK) st = model_runner_create(spec->nn, 4096, NBRDF_NN_INFER, &run_s, err);
  float *wi = dirs, *wo = dirs + 3 * all, *f = dirs + 6 * all;
  for (size_t k = 0; st == NBRDF_OK && k < n; k++) {
    const double *ref = images + k * all;
    float *z = net + k * (D + 2);
    double phi[BAKE_LOBE_N_THETA];
    for (int i = 0; i < BAKE_LOBE_N_THETA; i++)
      phi[i] = bake_lobe_azimuth(seed, k, i);
    st = decode_lobes(model->decoder, &run_u, z, res, phi, lat, wi, wo, f, img, err);
    if (st == NBRDF_OK) errs[n + k] = errs[k] = lobe_error(all, ref, img);
    if (st == NBRDF_OK && c) {
      bake_correct_latents(c, t, &k, 1, net, (size_t)(D + 2));
      if (compact) bake_compact_reduce(compact, z, coords);
      st = decode_lobes(spec, &run_s, compact ? coords : z, res, phi, lat, wi, wo, f, img, err);
      if (st == NBRDF_OK) errs[k] = lobe_error(all, ref, img);
    }
  }
  if (st == NBRDF_OK) {
    if (per_tuple) memcpy(per_tuple, errs, sizeof(double) * 2 * n);
    if (c && fitted) *fitted = median(errs, n);
    if (fast) *fast = median(errs + n, n);
  }
  model_runner_destroy(&run_u);
  model_runner_destroy(&run_s);
  free(net), free(lat), free(dirs), free(img), free(errs);
  return st;
}
