/* Helpers of the layered-BRDF tests: handles from parameters, queries from
 * angles in degrees, one-query evaluation. */
#ifndef NBRDF_TESTS_LAYERED_UTIL_H
#define NBRDF_TESTS_LAYERED_UTIL_H

#include <stdlib.h>
#include <string.h>

#include "core/vec3.h"
#include "nbrdf/brdf.h"
#include "testing.h"

static inline nbrdf_brdf *conductor_or_die(double alpha, double r0) {
  nbrdf_error err_ = {0}, *err = &err_;
  nbrdf_brdf *b = NULL;
  if (nbrdf_brdf_create_conductor(alpha, r0, &b, err)) {
    fprintf(stderr, "conductor(%g, %g): %s\n", alpha, r0, err->message);
    exit(2);
  }
  return b;
}

static inline nbrdf_brdf *layered_or_die(double alpha1, double eta, double albedo, double sigma_t,
                                         const nbrdf_brdf *bottom) {
  nbrdf_error err_ = {0}, *err = &err_;
  nbrdf_brdf *b = NULL;
  if (nbrdf_brdf_create_layered(alpha1, eta, albedo, sigma_t, bottom, &b, err)) {
    fprintf(stderr, "layered(%g, %g, %g, %g): %s\n", alpha1, eta, albedo, sigma_t, err->message);
    exit(2);
  }
  return b;
}

/* A layered BRDF over a conductor (the bottom handle is released). */
static inline nbrdf_brdf *layered2(double alpha1, double eta, double alpha2, double r0,
                                   double albedo, double sigma_t) {
  nbrdf_brdf *c = conductor_or_die(alpha2, r0);
  nbrdf_brdf *l = layered_or_die(alpha1, eta, albedo, sigma_t, c);
  nbrdf_brdf_destroy(c);
  return l;
}

static inline void set_dir(double w[3], double theta_deg, double phi_deg) {
  vec3 v = v3_from_spherical(theta_deg * M_PI / 180.0, phi_deg * M_PI / 180.0);
  w[0] = v.x;
  w[1] = v.y;
  w[2] = v.z;
}

static inline nbrdf_query query_deg(double ti, double pi, double to, double po) {
  nbrdf_query q;
  set_dir(q.wi, ti, pi);
  set_dir(q.wo, to, po);
  return q;
}

/* f and its standard error for one query (spp walks, seed). */
static inline double eval1(const nbrdf_brdf *b, nbrdf_query q, int spp, uint64_t seed, double *se) {
  nbrdf_eval_options o = NBRDF_EVAL_OPTIONS_DEFAULT;
  o.spp = spp;
  o.seed = seed;
  nbrdf_error err_ = {0}, *err = &err_;
  double f = NAN, s = NAN;
  CHECK_OK(nbrdf_brdf_eval(b, 1, &q, &o, &f, &s, err), err);
  if (se) *se = s;
  return f;
}

#endif
