/* Cheaper screens for the energy audit (docs/BAKE.md, "Cost"), measured against
 * the audit's own measurement (bake_albedo_precise: the polar rule at the six
 * angles of bake_audit_theta_deg) on every latent of a set:
 *
 *   bench_audit_screen [--bundle DIR] (--texture FILE | --bases N [--sharp] [--seed S])
 *                      [--samples N]... [--k K]
 *
 * 1. Fewer angles: for subsets S of the six angles, how often the largest albedo
 *    is at an angle of S, and how far the maximum over all six is above the
 *    maximum over S (the deficit a bound "max over S + delta" must cover).
 * 2. The sampling network's proxy: an importance-sampled estimate with N
 *    directions per angle (model_albedo_decoded_proxy: cosine + the latent's
 *    proxy Gaussian, jittered strata, fixed seed) and its standard error; a latent
 *    passes when max over angles of (estimate + K stderr) <= BAKE_AUDIT_LIMIT. Prints
 *    the share that passes, the largest polar value among those that pass (a pass
 *    above the limit would be a miss) and the largest (polar - upper bound).
 *
 * Tuples (--bases) are drawn uniformly in normalised parameters over the trained
 * range, or with --sharp from the clearcoat of bench/audit_cost.sh; --texture takes
 * every level-0 latent of a baked texture. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_audit.h"
#include "bake/bake_tuple.h"
#include "bench_clock.h"
#include "bench_sgemm.h"
#include "core/rng.h"
#include "model/albedo_quad.h"
#include "model/bundle.h"
#include "model/material.h"
#include "model/netio.h"
#include "nbrdf/bake.h"
#include "texture/latent_exr.h"

enum { P = NBRDF_BAKE_PARAM_COUNT, T = BAKE_AUDIT_N_THETA };

static int fail(const nbrdf_error *err) {
  fprintf(stderr, "bench_audit_screen: %s\n", err->message);
  return 1;
}

static int load_texture(const char *file, size_t *n_out, int *D_out, float **lat, float **sig,
                        nbrdf_error *err) {
  texture_latent_reader *r = NULL;
  if (texture_latent_reader_open(&r, file, err) != NBRDF_OK) return 1;
  const texture_latent_info *info = texture_latent_reader_info(r);
  const int C = texture_latent_colours(&info->layout), D = info->layout.latent_dim;
  const size_t texels = (size_t)info->width * info->height, n = texels * C;
  float *tex = malloc(texels * info->channels * sizeof *tex);
  *lat = malloc(n * D * sizeof **lat), *sig = malloc(n * sizeof **sig);
  if (texture_latent_reader_read(r, 0, 0, 0, info->width, info->height, tex, err) != NBRDF_OK)
    return 1;
  for (size_t i = 0; i < texels; i++)
    for (int c = 0; c < C; c++) {
      for (int j = 0; j < D; j++)
        (*lat)[(i * C + c) * D + j] =
            tex[i * info->channels + texture_latent_index_latent(&info->layout, c, j)];
      (*sig)[i * C + c] = tex[i * info->channels + texture_latent_index_sigma(&info->layout, c)];
    }
  free(tex);
  texture_latent_reader_close(r);
  *n_out = n, *D_out = D;
  return 0;
}

int main(int argc, char **argv) {
  const char *bundle = NULL, *file = NULL;
  int bases = 256, sharp = 0, n_samples = 0, samples[8];
  double k_se = 3.0;
  unsigned long long seed = 13;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--bundle") && i + 1 < argc)
      bundle = argv[++i];
    else if (!strcmp(argv[i], "--bases") && i + 1 < argc)
      bases = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--sharp"))
      sharp = 1;
    else if (!strcmp(argv[i], "--seed") && i + 1 < argc)
      seed = strtoull(argv[++i], NULL, 10);
    else if (!strcmp(argv[i], "--texture") && i + 1 < argc)
      file = argv[++i];
    else if (!strcmp(argv[i], "--samples") && i + 1 < argc && n_samples < 8)
      samples[n_samples++] = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--k") && i + 1 < argc)
      k_se = atof(argv[++i]);
  }
  if (!n_samples) samples[n_samples++] = 32, samples[n_samples++] = 64;
  nbrdf_error err = {0};
  nbrdf_model *model = NULL;
  if ((bundle ? nbrdf_model_load(bundle, &model, &err)
              : nbrdf_model_load_default(&model, NULL, 0, &err)) != NBRDF_OK)
    return fail(&err);
  size_t n;
  int D;
  float *lat = NULL, *sig = NULL;
  double *ua1 = NULL;     /* normalised alpha1 per latent (--bases only) */
  bake_tuple *tup = NULL; /* the tuples (--bases only) */
  if (file) {
    if (load_texture(file, &n, &D, &lat, &sig, &err)) return fail(&err);
  } else {
    float lo[P], hi[P];
    model_material_ranges(model, lo, hi);
    D = nbrdf_model_latent_dim(model);
    n = (size_t)bases;
    bake_tuple *t = calloc(n, sizeof *t);
    float *out = malloc(n * (D + 2) * sizeof *out);
    core_rng rng;
    core_rng_init(&rng, seed, sharp);
    for (size_t b = 0; b < n; b++) {
      double u[P];
      for (int id = 0; id < P; id++)
        u[id] = core_rng_uniform(&rng);
      if (sharp) {
        u[NBRDF_BAKE_ALPHA1] = 0.0;
        u[NBRDF_BAKE_ETA] = model_material_normalise(lo, hi, NBRDF_BAKE_ETA, 1.45f);
        u[NBRDF_BAKE_ALBEDO] = model_material_normalise(lo, hi, NBRDF_BAKE_ALBEDO, 0.8f);
        u[NBRDF_BAKE_SIGMA_T] = model_material_normalise(lo, hi, NBRDF_BAKE_SIGMA_T, 1.0f);
        u[NBRDF_BAKE_R0] = 0.5 + 0.5 * u[NBRDF_BAKE_R0];
      }
      for (int id = 0; id < P; id++)
        t[b].p[id] = model_material_unnormalise(lo, hi, id, u[id]);
      if (!ua1) ua1 = malloc(n * sizeof *ua1);
      ua1[b] = u[NBRDF_BAKE_ALPHA1];
    }
    if (bake_tuples_evaluate(model, t, NULL, n, out, &err) != NBRDF_OK) return fail(&err);
    lat = malloc(n * D * sizeof *lat), sig = malloc(n * sizeof *sig);
    for (size_t k = 0; k < n; k++) {
      memcpy(lat + k * D, out + k * (D + 2), D * sizeof *lat);
      sig[k] = out[k * (D + 2) + D];
    }
    tup = t;
    free(out);
  }
  model_runner runner;
  if (model_runner_create(model->decoder->nn, 4096, NBRDF_NN_INFER, &runner, &err) != NBRDF_OK)
    return fail(&err);
  double *rp = malloc(n * T * sizeof *rp), *rs = malloc(n * T * sizeof *rs);
  double *se = malloc(n * T * sizeof *se), *mx = malloc(n * sizeof *mx);
  double c0 = bench_cpu_seconds();
  if (model_albedo_decoded_polar(model->decoder, &runner, n, lat, T, bake_audit_theta_deg,
                                 BAKE_AUDIT_POLAR_RINGS, BAKE_AUDIT_POLAR_PHI, rp,
                                 &err) != NBRDF_OK)
    return fail(&err);
  double c1 = bench_cpu_seconds();
  const int q_polar = T * (BAKE_AUDIT_POLAR_RINGS * BAKE_AUDIT_POLAR_PHI + 1);
  printf("%s: %zu latents; polar rule %d queries each, %.2f CPU-s = %.3f us per query\n",
         file    ? file
         : sharp ? "sharp clearcoat tuples"
                 : "tuples over the whole range",
         n, q_polar, c1 - c0, 1e6 * (c1 - c0) / ((double)n * q_polar));
  /* The decoder's rate against the machine's sgemm at its widest shapes (rows x 96 x 96). */
  printf("decoder: %.1f GFLOP/s (2 x %.0f MACs per query); cblas_sgemm 4096 x 96 x 96: %.1f, "
         "256 x 96 x 96: %.1f, 4096 x 1024 x 1024: %.1f GFLOP/s (CPU time)\n",
         2.0 * (double)nn_spec_macs(nn_get_spec(model->decoder->nn)) * (double)n * q_polar /
             (c1 - c0) * 1e-9,
         (double)nn_spec_macs(nn_get_spec(model->decoder->nn)),
         bench_sgemm_gflops(4096, 96, 96, 0.3, 1), bench_sgemm_gflops(256, 96, 96, 0.3, 1),
         bench_sgemm_gflops(4096, 1024, 1024, 0.5, 1));
  int hist[T] = {0};
  double top = 0.0;
  for (size_t k = 0; k < n; k++) {
    int b = 0;
    for (int a = 1; a < T; a++)
      if (rp[k * T + a] > rp[k * T + b]) b = a;
    mx[k] = rp[k * T + b], hist[b]++;
    top = fmax(top, mx[k]);
  }
  printf("largest albedo (polar) %.4f; where the maximum is:", top);
  for (int a = 0; a < T; a++)
    printf(" %g deg %.1f %%", bake_audit_theta_deg[a], 100.0 * hist[a] / (double)n);
  printf("\n");
  /* subsets of angles (bit a: bake_audit_theta_deg[a]) */
  static const int subsets[] = {0x20, 0x21, 0x30, 0x31, 0x29, 0x38, 0x39, 0x3a};
  for (size_t s = 0; s < sizeof subsets / sizeof subsets[0]; s++) {
    double deficit = 0.0, deficit_hi = 0.0;
    size_t at = 0;
    for (size_t k = 0; k < n; k++) {
      double m = -1.0;
      for (int a = 0; a < T; a++)
        if (subsets[s] >> a & 1) m = fmax(m, rp[k * T + a]);
      at += mx[k] == m;
      deficit = fmax(deficit, mx[k] - m);
      if (mx[k] > 0.8) deficit_hi = fmax(deficit_hi, mx[k] - m);
    }
    printf("  angles {");
    for (int a = 0, first = 1; a < T; a++)
      if (subsets[s] >> a & 1)
        printf("%s%g", first ? "" : ", ", bake_audit_theta_deg[a]), first = 0;
    printf("}: maximum there %.1f %%; all six minus these: up to %.4f (%.4f where > 0.8)\n",
           100.0 * at / (double)n, deficit, deficit_hi);
  }
  /* The screen {0, 85, 89}: the deficit by where its own maximum is. */
  {
    double gap[3] = {0}, grow = 0.0, grow2 = 0.0;
    size_t cnt[3] = {0}, n_grow = 0, n_grow2 = 0;
    for (size_t k = 0; k < n; k++) {
      const double *r = rp + k * T;
      int b = r[0] >= r[4] && r[0] >= r[5] ? 0 : r[4] >= r[5] ? 1 : 2;
      double m = fmax(r[0], fmax(r[4], r[5]));
      gap[b] = fmax(gap[b], mx[k] - m), cnt[b]++;
      /* rising towards grazing: rho(0) <= rho(85) <= rho(89) */
      if (r[0] <= r[4] && r[4] <= r[5]) grow = fmax(grow, mx[k] - m), n_grow++;
      if (r[0] <= r[5]) grow2 = fmax(grow2, mx[k] - r[5]), n_grow2++;
    }
    printf("  screen {0, 85, 89} by where its maximum is: at 0 deg %zu latents, deficit up to "
           "%.4f; at 85 deg %zu, %.4f; at 89 deg %zu, %.4f; rising from 0 to 85 to 89 deg %zu, "
           "%.4f\n",
           cnt[0], gap[0], cnt[1], gap[1], cnt[2], gap[2], n_grow, grow);
    /* the tuple the screen misses most (a test's case: it must be measured at all six) */
    size_t worst_k = 0;
    double worst_gap = -1.0;
    for (size_t k = 0; tup && k < n; k++) {
      const double *r = rp + k * T;
      double g = mx[k] - fmax(r[0], fmax(r[4], r[5]));
      if (g > worst_gap) worst_gap = g, worst_k = k;
    }
    if (tup)
      printf("  largest miss of the screen %.4f (six angles %.4f) at alpha1 %g eta %g alpha2 %g "
             "r0 %g albedo %g sigma_t %g\n",
             worst_gap, mx[worst_k], (double)tup[worst_k].p[0], (double)tup[worst_k].p[1],
             (double)tup[worst_k].p[2], (double)tup[worst_k].p[3], (double)tup[worst_k].p[4],
             (double)tup[worst_k].p[5]);
    printf("  screen {0, 89}, rho(0) <= rho(89): %zu latents, deficit up to %.4f\n", n_grow2,
           grow2);
  }
  /* By the sampler's proxy width sigma (free: the bake stores it): the deficit of
   * {89} and of {85, 89} for sigma below each threshold. */
  {
    static const double below[] = {0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1e9};
    for (size_t s = 0; s < sizeof below / sizeof below[0]; s++) {
      double d89 = 0.0, d8589 = 0.0;
      size_t cnt = 0;
      for (size_t k = 0; k < n; k++) {
        if (!(sig[k] < below[s])) continue;
        const double *r = rp + k * T;
        cnt++, d89 = fmax(d89, mx[k] - r[5]), d8589 = fmax(d8589, mx[k] - fmax(r[4], r[5]));
      }
      printf("  proxy sigma < %g: %zu latents; all six minus {89}: up to %.4f, minus {85, 89}: "
             "%.4f\n",
             below[s], cnt, d89, d8589);
    }
  }
  /* By normalised alpha1 (eighths, the audit's grid): the deficit of {89}, {85, 89}. */
  for (int g = 0; ua1 && g < BAKE_AUDIT_GRID; g++) {
    double d89 = 0.0, d8589 = 0.0;
    size_t cnt = 0;
    for (size_t k = 0; k < n; k++) {
      if ((int)(ua1[k] * BAKE_AUDIT_GRID) != g) continue;
      const double *r = rp + k * T;
      cnt++, d89 = fmax(d89, mx[k] - r[5]), d8589 = fmax(d8589, mx[k] - fmax(r[4], r[5]));
    }
    printf("  normalised alpha1 in [%d, %d)/8: %zu latents; all six minus {89}: up to %.4f, minus "
           "{85, 89}: %.4f\n",
           g, g + 1, cnt, d89, d8589);
  }
  for (int j = 0; j < n_samples; j++) {
    double d0 = bench_cpu_seconds();
    if (model_albedo_decoded_proxy(model->decoder, &runner, n, lat, sig, T, bake_audit_theta_deg,
                                   samples[j], UINT64_C(0x73637265), rs, se, &err) != NBRDF_OK)
      return fail(&err);
    double d1 = bench_cpu_seconds();
    size_t pass = 0;
    double diff_lo = 0.0, diff_hi = 0.0, miss = -INFINITY, pass_top = -1.0, se_med = 0.0;
    double *ses = malloc(n * sizeof *ses);
    for (size_t k = 0; k < n; k++) {
      double up = -INFINITY, smax = 0.0;
      for (int a = 0; a < T; a++) {
        double e = rs[k * T + a] - rp[k * T + a];
        diff_lo = fmin(diff_lo, e), diff_hi = fmax(diff_hi, e);
        up = fmax(up, rs[k * T + a] + k_se * se[k * T + a]);
        smax = fmax(smax, se[k * T + a]);
      }
      ses[k] = smax;
      miss = fmax(miss, mx[k] - up);
      if (up <= BAKE_AUDIT_LIMIT) pass++, pass_top = fmax(pass_top, mx[k]);
    }
    for (size_t k = 0; k < n; k++) { /* median of the largest stderr per latent */
      size_t below = 0;
      for (size_t i = 0; i < n; i++)
        below += ses[i] < ses[k];
      if (below == n / 2) se_med = ses[k];
    }
    free(ses);
    printf("proxy + cosine, %d directions per angle (%d queries, %.2f CPU-s): estimate minus "
           "polar %.4f .. %+.4f; median largest stderr %.4f; pass (estimate + %g stderr <= "
           "%.2f at every angle) %.1f %%, largest polar value of those %.4f; polar minus upper "
           "bound up to %+.4f\n",
           samples[j], T * samples[j], d1 - d0, diff_lo, diff_hi, se_med, k_se, BAKE_AUDIT_LIMIT,
           100.0 * pass / (double)n, pass_top, miss);
  }
  model_runner_destroy(&runner);
  free(rp), free(rs), free(se), free(mx), free(lat), free(sig), free(ua1), free(tup);
  nbrdf_model_destroy(model);
  return 0;
}
