/* Shared checks of a BSDF's sampler against its pdf and eval, for the tests
 * of src/brdf (static: each test includes what it uses). */
#ifndef NBRDF_TESTS_BSDF_CHECK_H
#define NBRDF_TESTS_BSDF_CHECK_H

#include "brdf/bsdf.h"
#include "core/rng.h"
#include "core/warp.h"
#include "testing.h"

enum { CHECK_NC = 24, CHECK_NP = 16, CHECK_SUB = 16 };

/* A direction at the centre of sub-cell (a, b) of cell (i, j) of the grid
 * uniform in cos θ ∈ [−1, 1] and φ ∈ [−π, π). */
static inline vec3 check_cell_dir(int i, int j, int a, int b, int sub) {
  double c = -1.0 + 2.0 * (i + (a + 0.5) / sub) / CHECK_NC;
  double phi = -M_PI + 2.0 * M_PI * (j + (b + 0.5) / sub) / CHECK_NP;
  double s = sqrt(fmax(0.0, 1.0 - c * c));
  return v3(s * cos(phi), s * sin(phi), c);
}

static inline void check_cell_of(vec3 w, int *i, int *j) {
  *i = (int)((w.z + 1.0) * 0.5 * CHECK_NC);
  *j = (int)((atan2(w.y, w.x) + M_PI) / (2.0 * M_PI) * CHECK_NP);
  if (*i >= CHECK_NC) *i = CHECK_NC - 1;
  if (*i < 0) *i = 0;
  if (*j >= CHECK_NP) *j = CHECK_NP - 1;
  if (*j < 0) *j = 0;
}

/* Draws n samples of b from wo and checks, for a deterministic (analytic)
 * BSDF: every sample's pdf equals brdf_bsdf_pdf, its f equals brdf_bsdf_eval and its
 * weight equals f |cos| / pdf; the histogram over the sphere's cells matches
 * the pdf integrated over each cell (5 standard deviations + quadrature); the
 * pdf integrated over the sphere equals the fraction of successful draws. */
static void check_sampler(const char *label, const brdf_bsdf *b, vec3 wo, brdf_bsdf_mode mode,
                          int flags, int n, uint64_t seed) {
  static int hist[CHECK_NC][CHECK_NP];
  for (int i = 0; i < CHECK_NC; i++)
    for (int j = 0; j < CHECK_NP; j++)
      hist[i][j] = 0;
  core_rng rng;
  core_rng_init(&rng, seed, 0);
  int ok = 0, bad_values = 0;
  for (int s = 0; s < n; s++) {
    brdf_bsdf_sample bs;
    if (!brdf_bsdf_sample_dir(b, wo, mode, flags, &rng, &bs)) continue;
    ok++;
    double pdf = brdf_bsdf_pdf(b, wo, bs.wi, mode, flags);
    double f = brdf_bsdf_eval(b, wo, bs.wi, mode, NULL);
    double w = f * fabs(bs.wi.z) / pdf;
    int good = fabs(v3_length(bs.wi) - 1.0) < 1e-9 && isfinite(bs.weight) && bs.weight >= 0 &&
               fabs(pdf - bs.pdf) <= 1e-7 * pdf && fabs(f - bs.f) <= 1e-7 * f + 1e-300 &&
               fabs(w - bs.weight) <= 1e-7 * w;
    if (!good && bad_values++ < 3)
      fprintf(
          stderr,
          "%s: sample (%g, %g, %g): pdf %.12g vs %.12g, f %.12g vs %.12g, weight %.12g vs %.12g\n",
          label, bs.wi.x, bs.wi.y, bs.wi.z, bs.pdf, pdf, bs.f, f, bs.weight, w);
    int i, j;
    check_cell_of(bs.wi, &i, &j);
    hist[i][j]++;
  }
  CHECK_MSG(bad_values == 0, "%s: %d samples disagree with pdf/eval", label, bad_values);
  double total = 0.0;
  int bad_cells = 0;
  for (int i = 0; i < CHECK_NC; i++)
    for (int j = 0; j < CHECK_NP; j++) {
      double integral = 0.0;
      for (int a = 0; a < CHECK_SUB; a++)
        for (int c = 0; c < CHECK_SUB; c++)
          integral += brdf_bsdf_pdf(b, wo, check_cell_dir(i, j, a, c, CHECK_SUB), mode, flags);
      integral *= (2.0 / CHECK_NC) * (2.0 * M_PI / CHECK_NP) / (CHECK_SUB * CHECK_SUB);
      total += integral;
      double e = n * integral;
      if (fabs(hist[i][j] - e) > 5.0 * sqrt(e) + 0.02 * e + 3.0) {
        if (bad_cells++ < 5)
          fprintf(stderr, "%s: cell (%d, %d) has %d samples, pdf integral says %.1f\n", label, i, j,
                  hist[i][j], e);
      }
    }
  CHECK_MSG(bad_cells == 0, "%s: %d cells off", label, bad_cells);
  double frac = (double)ok / n;
  CHECK_MSG(fabs(total - frac) < 5.0 * sqrt(frac * (1 - frac) / n) + 0.01,
            "%s: pdf integrates to %.5f, %.5f of the draws succeed", label, total, frac);
}

#endif
