/* Speed of the layered ground truth: Monte Carlo walks (samples) per second
 * per core for three representative layered BRDFs, with the noise of one
 * walk, beside the machine's own cblas_sgemm rate measured in the same run
 * (METRICS.md "Speed"). Prints a markdown table.
 *
 *   bench_walk [--seconds S] [--threads T] [--lobe]   (defaults: 3 s per BRDF, 1 thread)
 *
 * --lobe adds the whole-lobe estimator (src/brdf/layered_lobe.c) against
 * per-pixel evaluation on a 64×64 lobe image at θi = 30°: the seed-to-seed
 * lobe error (METRICS.md) each reaches in the same CPU time, and the implied
 * speed-up (error ratio squared).
 *
 * Queries: 4 incidences θi ∈ {0, 30, 60, 80}° × 16 outgoing directions spread
 * over the hemisphere (METRICS.md lobe angles). "walks/s/core" divides by the
 * process CPU time, so it is meaningful on a shared machine; "walks/s" is
 * wall-clock. "noise/walk" is the mean over queries of stderr·√spp / f: the
 * relative standard deviation of one walk (lower is better; efficiency =
 * walks/s / noise²). */
#include <cblas.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "brdf/brdf_handle.h"
#include "brdf/layered_lobe.h"
#include "core/vec3.h"
#include "nbrdf/brdf.h"

#include "bench_clock.h"
#include "bench_sgemm.h"

static void die(nbrdf_status st, const nbrdf_error *err) {
  if (st == NBRDF_OK) return;
  fprintf(stderr, "bench_walk: %s\n", err->message);
  exit(1);
}

typedef struct bench_case {
  const char *name;
  double alpha1, eta, alpha2, r0, albedo, sigma_t;
} bench_case;

enum { NQ = 64 };

static void make_queries(nbrdf_query *q) {
  const double thetas[4] = {0, 30, 60, 80};
  for (int t = 0; t < 4; t++) {
    double ti = thetas[t] * M_PI / 180;
    for (int j = 0; j < 16; j++) {
      /* 16 outgoing directions: 4 rings × 4 azimuths, including the mirror one */
      double to = (10.0 + 20.0 * (j / 4)) * M_PI / 180, po = M_PI * 0.5 * (j % 4);
      nbrdf_query *qq = &q[16 * t + j];
      qq->wi[0] = sin(ti), qq->wi[1] = 0, qq->wi[2] = cos(ti);
      qq->wo[0] = sin(to) * cos(po), qq->wo[1] = sin(to) * sin(po), qq->wo[2] = cos(to);
    }
  }
}

enum { RES = 64 };

static double lobe_error(const double *ref, const double *x) {
  double num = 0.0, den = 0.0;
  for (int k = 0; k < RES * RES; k++) {
    num += fabs(x[k] - ref[k]);
    den += fabs(ref[k]);
  }
  return num / den;
}

/* The lobe image by per-pixel evaluation (spp walks per pixel). */
static void lobe_per_pixel(const nbrdf_brdf *b, double theta_i, int spp, uint64_t seed, int threads,
                           double *img) {
  static nbrdf_query q[RES * RES];
  static double f[RES * RES];
  int at[RES * RES], n = 0;
  for (int row = 0; row < RES; row++)
    for (int col = 0; col < RES; col++) {
      double x = -1.0 + (col + 0.5) * 2.0 / RES, y = 1.0 - (row + 0.5) * 2.0 / RES;
      img[row * RES + col] = 0.0;
      if (x * x + y * y >= 1.0) continue;
      q[n].wi[0] = sin(theta_i), q[n].wi[1] = 0, q[n].wi[2] = cos(theta_i);
      q[n].wo[0] = x, q[n].wo[1] = y, q[n].wo[2] = sqrt(1 - x * x - y * y);
      at[n++] = row * RES + col;
    }
  nbrdf_eval_options o = NBRDF_EVAL_OPTIONS_DEFAULT;
  o.spp = spp;
  o.seed = seed;
  o.threads = threads;
  nbrdf_error err = {0};
  die(nbrdf_brdf_eval(b, (size_t)n, q, &o, f, NULL, &err), &err);
  for (int k = 0; k < n; k++)
    img[at[k]] = f[k] * q[k].wo[2];
}

static void bench_lobe(const char *name, const nbrdf_brdf *b, double seconds, int threads) {
  const double theta_i = 30.0 * M_PI / 180.0;
  static double a[RES * RES], c[RES * RES];
  const brdf_bsdf_layered *l = &brdf_handle_bsdf(b)->layered;
  /* calibrate both to about `seconds` of CPU time per image */
  double c0 = bench_cpu_seconds();
  lobe_per_pixel(b, theta_i, 8, 1, threads, a);
  int spp = (int)fmax(2.0, 8.0 * seconds / (bench_cpu_seconds() - c0));
  c0 = bench_cpu_seconds();
  if (!brdf_layered_lobe_image(l, theta_i, RES, 8, 1, threads, a, NULL)) exit(1);
  int walks = (int)fmax(2.0, 8.0 * seconds / (bench_cpu_seconds() - c0));
  c0 = bench_cpu_seconds();
  lobe_per_pixel(b, theta_i, spp, 2, threads, a);
  lobe_per_pixel(b, theta_i, spp, 3, threads, c);
  double t_pp = (bench_cpu_seconds() - c0) / 2, e_pp = lobe_error(a, c);
  c0 = bench_cpu_seconds();
  if (!brdf_layered_lobe_image(l, theta_i, RES, walks, 2, threads, a, NULL) ||
      !brdf_layered_lobe_image(l, theta_i, RES, walks, 3, threads, c, NULL))
    exit(1);
  double t_lobe = (bench_cpu_seconds() - c0) / 2, e_lobe = lobe_error(a, c);
  /* errors scale as 1/√time: compare at equal time */
  double e_lobe_eq = e_lobe * sqrt(t_lobe / t_pp);
  printf("| %s | %d spp/pixel, %.2f s: %.2f %% | %d walks, %.2f s: %.2f %% | %.1f× |\n", name, spp,
         t_pp, 100 * e_pp, walks, t_lobe, 100 * e_lobe, (e_pp / e_lobe_eq) * (e_pp / e_lobe_eq));
  fflush(stdout);
}

int main(int argc, char **argv) {
  double seconds = 3.0;
  int threads = 1, lobe = 0;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--seconds") && i + 1 < argc)
      seconds = atof(argv[++i]);
    else if (!strcmp(argv[i], "--lobe"))
      lobe = 1;
    else if (!strcmp(argv[i], "--threads") && i + 1 < argc)
      threads = atoi(argv[++i]);
    else {
      fprintf(stderr, "usage: bench_walk [--seconds S] [--threads T] [--lobe]\n");
      return 2;
    }
  }
  const bench_case cases[3] = {
      {"smooth coat over rough metal", 0.02, 1.5, 0.5, 0.9, 0.0, 0.0},
      {"rough coat over smooth metal", 0.6, 1.5, 0.02, 0.9, 0.0, 0.0},
      {"thick scattering medium", 0.1, 1.5, 0.3, 0.9, 0.95, 5.0},
  };
  nbrdf_query q[NQ];
  make_queries(q);
  double gf = bench_sgemm_gflops(4096, 256, 256, 1.0, 0) /* a decoder-layer shape */;
  printf("cblas_sgemm 4096x256x256: %.1f GFLOP/s (OpenBLAS threads: default)\n\n", gf);
  printf("| BRDF (α1, η, α2, R0, A, σT) | threads | spp | walks/s | walks/s/core (CPU time) | "
         "noise/walk | walks per GFLOP of sgemm |\n");
  printf("|---|---|---|---|---|---|---|\n");
  for (int c = 0; c < 3; c++) {
    const bench_case *bc = &cases[c];
    nbrdf_error err = {0};
    nbrdf_brdf *bottom = NULL, *l = NULL;
    die(nbrdf_brdf_create_conductor(bc->alpha2, bc->r0, &bottom, &err), &err);
    die(nbrdf_brdf_create_layered(bc->alpha1, bc->eta, bc->albedo, bc->sigma_t, bottom, &l, &err),
        &err);
    double f[NQ], se[NQ];
    nbrdf_eval_options o = NBRDF_EVAL_OPTIONS_DEFAULT;
    o.threads = threads;
    o.spp = 256; /* calibration */
    double t0 = bench_wall_seconds();
    die(nbrdf_brdf_eval(l, NQ, q, &o, f, se, &err), &err);
    double per_walk = (bench_wall_seconds() - t0) / (NQ * 256.0);
    o.spp = (int)fmax(256.0, seconds / (per_walk * NQ));
    o.seed = 1;
    double w0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
    die(nbrdf_brdf_eval(l, NQ, q, &o, f, se, &err), &err);
    double wt = bench_wall_seconds() - w0, ct = bench_cpu_seconds() - c0;
    double walks = (double)NQ * o.spp, noise = 0.0;
    int counted = 0;
    for (int k = 0; k < NQ; k++)
      if (f[k] > 0) {
        noise += se[k] * sqrt((double)o.spp) / f[k];
        counted++;
      }
    noise /= counted;
    printf("| %s (%g, %g, %g, %g, %g, %g) | %d | %d | %.3g | %.3g | %.2f | %.3g |\n", bc->name,
           bc->alpha1, bc->eta, bc->alpha2, bc->r0, bc->albedo, bc->sigma_t, threads, o.spp,
           walks / wt, walks / ct, noise, walks / ct / gf);
    fflush(stdout);
    nbrdf_brdf_destroy(l);
    nbrdf_brdf_destroy(bottom);
  }
  if (!lobe) return 0;
  printf("\nSeed-to-seed lobe error of a 64x64 lobe image at θi = 30° (two seeds), per-pixel "
         "evaluation vs the whole-lobe estimator, CPU time per image:\n\n");
  printf("| BRDF | per-pixel eval | whole-lobe estimator | speed-up at equal error |\n");
  printf("|---|---|---|---|\n");
  for (int c = 0; c < 3; c++) {
    const bench_case *bc = &cases[c];
    nbrdf_error err = {0};
    nbrdf_brdf *bottom = NULL, *l = NULL;
    die(nbrdf_brdf_create_conductor(bc->alpha2, bc->r0, &bottom, &err), &err);
    die(nbrdf_brdf_create_layered(bc->alpha1, bc->eta, bc->albedo, bc->sigma_t, bottom, &l, &err),
        &err);
    bench_lobe(bc->name, l, seconds, threads);
    nbrdf_brdf_destroy(l);
    nbrdf_brdf_destroy(bottom);
  }
  return 0;
}
