/* Public handles: creation with parameter validation, copies, destruction. */
#include <stdio.h>
#include <stdlib.h>

#include "brdf/brdf_handle.h"
#include "core/error.h"

static nbrdf_status new_handle(const brdf_bsdf *b, nbrdf_brdf **out, nbrdf_error *err) {
  nbrdf_brdf *h = malloc(sizeof *h);
  if (!h || !brdf_bsdf_clone(&h->b, b)) {
    free(h);
    return core_fail(err, NBRDF_ERR_MEMORY, "out of memory creating a BRDF");
  }
  *out = h;
  return NBRDF_OK;
}

nbrdf_status nbrdf_brdf_create_conductor(double alpha, double r0, nbrdf_brdf **out,
                                         nbrdf_error *err) {
  if (!out) return core_fail(err, NBRDF_ERR_ARGUMENT, "conductor: out is NULL");
  *out = NULL;
  nbrdf_status st;
  if ((st = core_check_range(err, "alpha", alpha, NBRDF_GT_ALPHA_MIN, NBRDF_GT_ALPHA_MAX)) ||
      (st = core_check_range(err, "r0", r0, 0.0, 1.0))) {
    core_error_prefix(err, "conductor: ");
    return st;
  }
  brdf_bsdf b = {.kind = BSDF_CONDUCTOR, .conductor = {alpha, r0}};
  return new_handle(&b, out, err);
}

nbrdf_status nbrdf_brdf_create_dielectric(double alpha, double eta, nbrdf_brdf **out,
                                          nbrdf_error *err) {
  if (!out) return core_fail(err, NBRDF_ERR_ARGUMENT, "dielectric: out is NULL");
  *out = NULL;
  nbrdf_status st;
  if ((st = core_check_range(err, "alpha", alpha, NBRDF_GT_ALPHA_MIN, NBRDF_GT_ALPHA_MAX)) ||
      (st = core_check_range(err, "eta", eta, NBRDF_GT_ETA_MIN, NBRDF_GT_ETA_MAX))) {
    core_error_prefix(err, "dielectric: ");
    return st;
  }
  brdf_bsdf b = {.kind = BSDF_DIELECTRIC, .dielectric = {alpha, eta}};
  return new_handle(&b, out, err);
}

nbrdf_status nbrdf_brdf_create_layered(double alpha1, double eta, double albedo, double sigma_t,
                                       const nbrdf_brdf *bottom, nbrdf_brdf **out,
                                       nbrdf_error *err) {
  if (!out) return core_fail(err, NBRDF_ERR_ARGUMENT, "layered: out is NULL");
  *out = NULL;
  nbrdf_status st;
  if ((st = core_check_range(err, "alpha1", alpha1, NBRDF_GT_ALPHA_MIN, NBRDF_GT_ALPHA_MAX)) ||
      (st = core_check_range(err, "eta", eta, NBRDF_GT_ETA_MIN, NBRDF_GT_ETA_MAX)) ||
      (st = core_check_range(err, "albedo", albedo, 0.0, 1.0)) ||
      (st = core_check_range(err, "sigma_t", sigma_t, 0.0, NBRDF_GT_SIGMA_T_MAX))) {
    core_error_prefix(err, "layered: ");
    return st;
  }
  if (!bottom) return core_fail(err, NBRDF_ERR_ARGUMENT, "layered: bottom is NULL");
  /* The bottom is copied by new_handle's deep clone (brdf_bsdf_clone), so the
   * caller may destroy it afterwards. */
  brdf_bsdf b = {.kind = BSDF_LAYERED,
                 .layered = {.top = {alpha1, eta},
                             .albedo = albedo,
                             .sigma_t = sigma_t,
                             .bottom = (brdf_bsdf *)&bottom->b}};
  return new_handle(&b, out, err);
}

void nbrdf_brdf_destroy(nbrdf_brdf *brdf) {
  if (!brdf) return;
  brdf_bsdf_release(&brdf->b);
  free(brdf);
}

int nbrdf_brdf_is_stochastic(const nbrdf_brdf *brdf) {
  return brdf && brdf_bsdf_is_stochastic(&brdf->b);
}

nbrdf_status brdf_check_direction(const double w[3], const char *what, vec3 *out,
                                  nbrdf_error *err) {
  vec3 v = v3(w[0], w[1], w[2]);
  if (!v3_is_finite(v))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s = (%g, %g, %g) is not finite", what, v.x, v.y,
                     v.z);
  if (!(v.z > 0.0))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s = (%g, %g, %g) has z <= 0 (must point into the upper hemisphere)", what,
                     v.x, v.y, v.z);
  double len = v3_length(v);
  if (!(fabs(len - 1.0) <= 1e-6))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s = (%g, %g, %g) is not a unit vector (length %.9g, tolerance 1e-6)", what,
                     v.x, v.y, v.z, len);
  *out = v3_scale(v, 1.0 / len);
  return NBRDF_OK;
}
