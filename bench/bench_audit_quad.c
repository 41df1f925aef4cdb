/* The energy audit's quadrature at fewer directions: how far the maximum over
 * θi of each candidate quadrature is from brute force (16,384 jittered
 * directions per angle with the ladder of techniques, another seed), on tuples
 * drawn over the whole trained range or (--sharp) on the clearcoat of
 * bench/audit_cost.sh. Candidates: the lattice with the ladder of GGX
 * techniques (bake_albedo_precise before the polar rule), and the polar
 * product rule (model_albedo_decoded_polar) at several ring counts.
 *
 * --corner: both lobes sharp (normalised alpha1 below 0.05, alpha2 below 0.15).
 *
 * --at a1,eta,a2,r0,albedo,sigma_t: that tuple with alpha2 swept over +-25 %, each
 * tuple's values printed.
 *
 *   bench_audit_quad [--bundle DIR] [--bases N] [--sharp | --corner | --at TUPLE] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_audit.h"
#include "bake/bake_tuple.h"
#include "bench_clock.h"
#include "core/rng.h"
#include "model/albedo_quad.h"
#include "model/bundle.h"
#include "model/material.h"
#include "model/netio.h"
#include "nbrdf/bake.h"

enum { P = NBRDF_BAKE_PARAM_COUNT };

static int fail(const nbrdf_error *err) {
  fprintf(stderr, "bench_audit_quad: %s\n", err->message);
  return 1;
}

static void max_theta(const double *rho, size_t n, double *mx) {
  for (size_t k = 0; k < n; k++) {
    mx[k] = -1.0;
    for (int a = 0; a < BAKE_AUDIT_N_THETA; a++)
      mx[k] = fmax(mx[k], rho[k * BAKE_AUDIT_N_THETA + a]);
  }
}

int main(int argc, char **argv) {
  const char *bundle = NULL;
  int n = 48, sharp = 0;
  const char *at = NULL;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--bundle") && i + 1 < argc)
      bundle = argv[++i];
    else if (!strcmp(argv[i], "--bases") && i + 1 < argc)
      n = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--sharp"))
      sharp = 1;
    else if (!strcmp(argv[i], "--corner"))
      sharp = 2;
    else if (!strcmp(argv[i], "--at") && i + 1 < argc)
      at = argv[++i];
  }
  nbrdf_error err = {0};
  nbrdf_model *model = NULL;
  if ((bundle ? nbrdf_model_load(bundle, &model, &err)
              : nbrdf_model_load_default(&model, NULL, 0, &err)) != NBRDF_OK)
    return fail(&err);
  float lo[P], hi[P];
  model_material_ranges(model, lo, hi);
  const int D = nbrdf_model_latent_dim(model);
  bake_tuple *t = calloc((size_t)n, sizeof *t);
  float *out = malloc((size_t)n * (D + 2) * sizeof *out);
  float *lat = malloc((size_t)n * D * sizeof *lat), *sig = malloc((size_t)n * sizeof *sig);
  double *rho = malloc((size_t)n * BAKE_AUDIT_N_THETA * sizeof *rho);
  double *brute = malloc((size_t)n * sizeof *brute);
  core_rng rng;
  core_rng_init(&rng, 12, sharp);
  for (int k = 0; k < n; k++)
    for (int id = 0; id < P; id++) {
      double u = core_rng_uniform(&rng);
      if (sharp == 2) { /* both lobes sharp */
        if (id == NBRDF_BAKE_ALPHA1) u *= 0.05;
        if (id == NBRDF_BAKE_ALPHA2) u *= 0.15;
      } else if (sharp) {
        if (id == NBRDF_BAKE_ALPHA1) u = 0.0;
        if (id == NBRDF_BAKE_ETA) u = model_material_normalise(lo, hi, id, 1.45f);
        if (id == NBRDF_BAKE_ALBEDO) u = model_material_normalise(lo, hi, id, 0.8f);
        if (id == NBRDF_BAKE_SIGMA_T) u = model_material_normalise(lo, hi, id, 1.0f);
        if (id == NBRDF_BAKE_R0) u = 0.5 + 0.5 * u;
      }
      t[k].p[id] = model_material_unnormalise(lo, hi, id, u);
    }
  if (at) { /* one tuple, alpha2 swept over +-25 % */
    float b[P];
    if (sscanf(at, "%f,%f,%f,%f,%f,%f", &b[0], &b[1], &b[2], &b[3], &b[4], &b[5]) != P) {
      fprintf(stderr, "bench_audit_quad: --at a1,eta,a2,r0,albedo,sigma_t\n");
      return 2;
    }
    for (int k = 0; k < n; k++) {
      memcpy(t[k].p, b, sizeof b);
      t[k].p[NBRDF_BAKE_ALPHA2] = b[NBRDF_BAKE_ALPHA2] * (0.75f + 0.5f * (float)k / (float)(n - 1));
    }
  }
  if (bake_tuples_evaluate(model, t, NULL, (size_t)n, out, &err) != NBRDF_OK) return fail(&err);
  for (int k = 0; k < n; k++) {
    memcpy(lat + (size_t)k * D, out + (size_t)k * (D + 2), D * sizeof *lat);
    sig[k] = out[(size_t)k * (D + 2) + D];
  }
  model_runner runner;
  if (model_runner_create(model->decoder->nn, 4096, NBRDF_NN_INFER, &runner, &err) != NBRDF_OK)
    return fail(&err);
  if (model_albedo_decoded(model->decoder, &runner, (size_t)n, lat, sig, BAKE_AUDIT_N_THETA,
                           bake_audit_theta_deg, 16384, UINT64_C(0x62727574), rho, NULL,
                           &err) != NBRDF_OK)
    return fail(&err);
  max_theta(rho, (size_t)n, brute);
  double top = -1;
  for (int k = 0; k < n; k++)
    top = fmax(top, brute[k]);
  printf("%d tuples (%s), largest brute-force albedo %.4f\n", n,
         sharp == 2 ? "sharp coat over a sharp base"
         : sharp    ? "sharp clearcoat"
                    : "whole range",
         top);
  /* lattice: directions per angle; polar: rings × azimuths (+ 1 node) */
  const int lattice[] = {128, 256, 1024}, rings[] = {12, 16, 24, 32, 48, 48, 96},
            phis[] = {8, 8, 8, 8, 8, 16, 32};
  const int n_lat = sizeof lattice / sizeof *lattice, n_pol = sizeof rings / sizeof *rings;
  const int rows = n_lat + n_pol;
  double *all = malloc((size_t)rows * n * sizeof *all), *ms = malloc((size_t)rows * sizeof *ms);
  for (int c = 0; c < rows; c++) {
    const int polar = c >= n_lat;
    const int count = polar ? phis[c - n_lat] * rings[c - n_lat] + 1 : lattice[c];
    double c0 = bench_cpu_seconds();
    nbrdf_status st =
        polar ? model_albedo_decoded_polar(model->decoder, &runner, (size_t)n, lat,
                                           BAKE_AUDIT_N_THETA, bake_audit_theta_deg,
                                           rings[c - n_lat], phis[c - n_lat], rho, &err)
              : model_albedo_decoded_lattice(model->decoder, &runner, (size_t)n, lat, sig,
                                             BAKE_AUDIT_N_THETA, bake_audit_theta_deg, count,
                                             UINT64_C(0x6175646974), rho, &err);
    if (st) return fail(&err);
    ms[c] = 1e3 * (bench_cpu_seconds() - c0) / n;
    max_theta(rho, (size_t)n, all + (size_t)c * n);
  }
  /* the finest polar rule (the last row) as a second reference */
  const double *fine = all + (size_t)(rows - 1) * n;
  printf("| quadrature | nodes per angle | CPU ms per latent | brute force minus it (max) | it "
         "minus brute force (max) | finest polar minus it (max) | it minus finest polar (max) |\n");
  printf("|---|---|---|---|---|---|---|\n");
  for (int c = 0; c < rows; c++) {
    const int polar = c >= n_lat;
    const int count = polar ? phis[c - n_lat] * rings[c - n_lat] + 1 : lattice[c];
    const double *v = all + (size_t)c * n;
    double down = 0, up = 0, fdown = 0, fup = 0;
    for (int k = 0; k < n; k++) {
      down = fmax(down, brute[k] - v[k]), up = fmax(up, v[k] - brute[k]);
      fdown = fmax(fdown, fine[k] - v[k]), fup = fmax(fup, v[k] - fine[k]);
    }
    char name[64];
    snprintf(name, sizeof name, polar ? "polar, %d rings of %d" : "lattice, ladder",
             polar ? rings[c - n_lat] : 0, polar ? phis[c - n_lat] : 0);
    printf("| %s | %d | %.2f | %.4f | %.4f | %.4f | %.4f |\n", name, count, ms[c], down, up, fdown,
           fup);
  }
  for (int k = 0; at && k < n; k++) {
    printf("alpha2 %.4f: brute force %.4f", (double)t[k].p[NBRDF_BAKE_ALPHA2], brute[k]);
    for (int c = 0; c < rows; c++)
      printf(" %.4f", all[(size_t)c * n + k]);
    printf("\n");
  }
  free(all), free(ms);
  model_runner_destroy(&runner);
  nbrdf_model_destroy(model);
  free(t), free(out), free(lat), free(sig), free(rho), free(brute);
  return 0;
}
