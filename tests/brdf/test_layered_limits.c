/* Limits of the layered BRDF that reduce it to something known exactly or
 * in closed form, so that the walk is checked against independent physics
 * and not only against itself. */
#include "brdf/fresnel.h"
#include "layered_util.h"

static const double dirs[][4] = {{0, 0, 0, 0},      {30, 0, 30, 180}, {30, 0, 50, 90},
                                 {60, 0, 60, 180},  {60, 0, 10, 0},   {80, 0, 80, 180},
                                 {89.9, 0, 45, 180}};
enum { NDIRS = sizeof dirs / sizeof dirs[0] };

/* η = 1 and σT = 0: the top is invisible and there is no slab, so the walk
 * returns the bottom's value exactly (zero variance), whatever α1 and A. */
static void test_index_matched_empty_slab_is_bottom(void) {
  nbrdf_brdf *c = conductor_or_die(0.3, 0.7);
  const double alpha1s[] = {0.01, 1.0};
  for (int a = 0; a < 2; a++) {
    nbrdf_brdf *l = layered_or_die(alpha1s[a], 1.0, 0.5, 0.0, c);
    for (int k = 0; k < NDIRS; k++) {
      nbrdf_query q = query_deg(dirs[k][0], dirs[k][1], dirs[k][2], dirs[k][3]);
      double se, f = eval1(l, q, 16, 1, &se), fc = eval1(c, q, 1, 1, NULL);
      CHECK_REL(f, fc, 1e-12, 1e-300);
      CHECK(se <= 1e-12 * fc);
    }
    nbrdf_brdf_destroy(l);
  }
  nbrdf_brdf_destroy(c);
}

/* A = 0 and σT = 50: nothing crosses the slab (e^-50), only the top's own
 * reflection remains — the dielectric's value. */
static void test_opaque_absorber_is_top(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  const double alpha1s[] = {0.05, 0.5}, etas[] = {1.05, 1.5, 2.0};
  for (int a = 0; a < 2; a++)
    for (int e = 0; e < 3; e++) {
      nbrdf_brdf *l = layered2(alpha1s[a], etas[e], 0.2, 1.0, 0.0, 50.0), *d = NULL;
      CHECK_OK(nbrdf_brdf_create_dielectric(alpha1s[a], etas[e], &d, err), err);
      for (int k = 0; k < NDIRS; k++) {
        nbrdf_query q = query_deg(dirs[k][0], dirs[k][1], dirs[k][2], dirs[k][3]);
        double se, f = eval1(l, q, 64, 2, &se), fd = eval1(d, q, 1, 1, NULL);
        CHECK_REL(f, fd, 1e-9, 1e-300);
      }
      nbrdf_brdf_destroy(l);
      nbrdf_brdf_destroy(d);
    }
}

/* R0 = 0 and A = 0: the bottom reflects only Schlick's (1 − cos θd)^5, tiny
 * for the near-normal directions that refraction leaves inside the coat, so
 * the top's reflection is nearly all (measured: within 0.3 % at 60°). */
static void test_black_bottom_is_nearly_top(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  nbrdf_brdf *l = layered2(0.2, 1.5, 0.05, 0.0, 0.0, 0.0), *d = NULL;
  CHECK_OK(nbrdf_brdf_create_dielectric(0.2, 1.5, &d, err), err);
  for (int k = 0; k < NDIRS - 1; k++) {
    nbrdf_query q = query_deg(dirs[k][0], dirs[k][1], dirs[k][2], dirs[k][3]);
    double se, f = eval1(l, q, 4096, 3, &se), fd = eval1(d, q, 1, 1, NULL);
    CHECK_MSG(f >= fd - 4 * se && f - fd <= 0.005 * fd + 4 * se, "dir %d: f %g top %g ± %g", k, f,
              fd, se);
  }
  nbrdf_brdf_destroy(l);
  nbrdf_brdf_destroy(d);
}

/* Single scattering of a slab of optical depth τ with isotropic phase:
 * f = A / (4π) · (1 − exp(−τ (1/μo + 1/μi))) / (μo + μi)  (Chandrasekhar).
 * Behind a smooth coat (α1 = 1e-3): f = To Ti / η² · f_ss(μo', μi') with the
 * refracted cosines (flux through the interface: radiance × η² inside,
 * solid angle × 1/η²). The bottom is black (an index-matched dielectric,
 * which neither reflects nor returns light), and A = 0.002 makes multiple
 * scattering a ~0.2 % correction. */
static double f_single(double albedo, double tau, double mo, double mi) {
  return albedo / (4 * M_PI) * (1 - exp(-tau * (1 / mo + 1 / mi))) / (mo + mi);
}

static void test_single_scattering(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  nbrdf_brdf *black = NULL;
  CHECK_OK(nbrdf_brdf_create_dielectric(0.5, 1.0, &black, err), err);
  const double etas[] = {1.0, 1.5}, taus[] = {0.3, 3.0};
  const double pairs[][2] = {{0, 40}, {30, 60}, {70, 20}};
  const double albedo = 0.002;
  for (int e = 0; e < 2; e++)
    for (int t = 0; t < 2; t++) {
      nbrdf_brdf *l = layered_or_die(1e-3, etas[e], albedo, taus[t], black);
      for (int p = 0; p < 3; p++) {
        /* φ differ by 90° so that the top's own specular lobe is far away. */
        nbrdf_query q = query_deg(pairs[p][0], 0, pairs[p][1], 90);
        double ti = pairs[p][0] * M_PI / 180, to = pairs[p][1] * M_PI / 180;
        double si = sin(ti) / etas[e], so = sin(to) / etas[e];
        double mi = sqrt(1 - si * si), mo = sqrt(1 - so * so);
        double transmit = (1 - brdf_fresnel_dielectric(cos(ti), etas[e])) *
                          (1 - brdf_fresnel_dielectric(cos(to), etas[e])) / (etas[e] * etas[e]);
        double expected = transmit * f_single(albedo, taus[t], mo, mi);
        double se, f = eval1(l, q, 20000, 4, &se);
        CHECK_MSG(fabs(f - expected) <= 4 * se + 0.006 * expected,
                  "eta %g tau %g (%g, %g): f %.6g ± %.2g, single scattering %.6g", etas[e], taus[t],
                  pairs[p][0], pairs[p][1], f, se, expected);
      }
      nbrdf_brdf_destroy(l);
    }
  nbrdf_brdf_destroy(black);
}

/* White furnace: a smooth coat over a mirror with a lossless medium loses
 * nothing (microfacet masking at α = 1e-3 is negligible), so the albedo is 1
 * — this checks the η² radiance scaling in and out of the coat. */
static void test_white_furnace(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  const double sigmas[] = {0.0, 1.0, 5.0}, thetas[] = {0.0, 45.0, 75.0};
  for (int s = 0; s < 3; s++) {
    nbrdf_brdf *l = layered2(1e-3, 1.5, 1e-3, 1.0, 1.0, sigmas[s]);
    for (int t = 0; t < 3; t++) {
      double rho, se;
      CHECK_OK(nbrdf_brdf_albedo(l, thetas[t] * M_PI / 180, 4000, 5, &rho, &se, err), err);
      CHECK_MSG(fabs(rho - 1.0) <= 4 * se + 2e-3, "sigma_t %g theta %g: albedo %.5f ± %.5f",
                sigmas[s], thetas[t], rho, se);
    }
    nbrdf_brdf_destroy(l);
  }
}

/* Three layers: an outer layer that is index-matched with an empty slab
 * reduces to its (layered) bottom, within the standard errors. */
static void test_three_layers_reduce(void) {
  nbrdf_brdf *inner = layered2(0.3, 1.5, 0.2, 0.9, 0.7, 1.0);
  nbrdf_brdf *outer = layered_or_die(0.5, 1.0, 0.3, 0.0, inner);
  for (int k = 0; k < NDIRS; k++) {
    nbrdf_query q = query_deg(dirs[k][0], dirs[k][1], dirs[k][2], dirs[k][3]);
    double sa, sb, fa = eval1(outer, q, 4096, 6, &sa), fb = eval1(inner, q, 4096, 7, &sb);
    CHECK_MSG(fabs(fa - fb) <= 4.5 * sqrt(sa * sa + sb * sb),
              "dir %d: 3 layers %g ± %g, 2 layers %g ± %g", k, fa, sa, fb, sb);
  }
  nbrdf_brdf_destroy(outer);
  nbrdf_brdf_destroy(inner);
}

int main(void) {
  RUN(test_index_matched_empty_slab_is_bottom);
  RUN(test_opaque_absorber_is_top);
  RUN(test_black_bottom_is_nearly_top);
  RUN(test_single_scattering);
  RUN(test_white_furnace);
  RUN(test_three_layers_reduce);
  return testing_finish();
}
