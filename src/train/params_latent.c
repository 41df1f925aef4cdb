#include "train/params_latent.h"

#include <string.h>

static nbrdf_status base(const nbrdf_model *m, nbrdf_base_kind kind, double p0, double p1,
                         float *out, nbrdf_error *err) {
  float f0 = (float)p0, f1 = (float)p1;
  return nbrdf_model_base_latents(m, kind, 1, &f0, &f1, NBRDF_RANGE_CLAMP, out, NULL, err);
}

nbrdf_status train_params_bundle_latent(const nbrdf_model *m, const train_params *p, float *out,
                                        nbrdf_error *err) {
  float below[64], top[64], next[64];
  nbrdf_status st = p->kind == TRAIN_DIELECTRIC
                        ? base(m, NBRDF_BASE_DIELECTRIC, p->base_alpha, p->base_eta, below, err)
                        : base(m, NBRDF_BASE_CONDUCTOR, p->base_alpha, p->base_r0, below, err);
  for (int c = p->n_coats - 1; c >= 0 && !st; c--) {
    const train_coat *k = &p->coat[c];
    float a = (float)k->albedo, s = (float)k->sigma_t;
    st = base(m, NBRDF_BASE_DIELECTRIC, k->alpha, k->eta, top, err);
    if (!st) st = nbrdf_model_layer(m, 1, top, below, &a, &s, next, err);
    if (!st) memcpy(below, next, sizeof next);
  }
  if (!st) memcpy(out, below, (size_t)nbrdf_model_latent_dim(m) * sizeof *out);
  return st;
}
