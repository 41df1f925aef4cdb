/* The energy audit's bound (src/bake/bake_audit.h): how fast the decoded
 * albedo moves per unit of normalised parameter (bake_audit_slope), how far the
 * audit's quadrature is from a brute-force one (BAKE_AUDIT_NOISE), and whether
 * representative + slopes + noise really bounds the tuples of a cell.
 *
 *   bench_audit_margin [--bundle DIR] [--bases N] [--sharp] [--no-brute] [--noise X]
 *                      [--seed S]
 *   bench_audit_margin [--bundle DIR] --texture FILE [--top K]
 *
 * Tuples are drawn uniformly in normalised parameters over the trained range,
 * or with --sharp from the clearcoat of bench/audit_cost.sh (alpha1 clamped to
 * the range's low end, eta 1.45, albedo 0.8, sigma_t 1; alpha2 and r0 drawn).
 * For each base tuple: one brute-force measurement (16,384 directions per
 * angle) against the audit's (bake_albedo_precise), steps of 1/32 to 1/4 along
 * each parameter (the slope each needs under the bound's noise), and one
 * random tuple of the base's cell checked against the bound. Prints the
 * largest of each. --no-brute skips the brute force (slopes only).
 *
 * --texture: every level-0 latent of a baked texture measured with the audit's
 * quadrature (no cells) and with the old audit's (bake_albedo_max: 32
 * directions, 1,024 above 0.9), and the K (8) largest of each brute-forced:
 * the texture's worst albedo as exactly as this machine affords, to compare
 * with the header's nbrdf:maxAlbedo. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_audit.h"
#include "bake/bake_tuple.h"
#include "model/material.h"
#include "nbrdf/bake.h"
#include "bench_clock.h"
#include "core/rng.h"
#include "model/albedo_quad.h"
#include "model/bundle.h"
#include "model/netio.h"
#include "texture/latent_exr.h"

enum { P = NBRDF_BAKE_PARAM_COUNT, R = BAKE_AUDIT_REGIONS };

static int region(double u) {
  int r = (int)(u * R);
  return r < 0 ? 0 : r >= R ? R - 1 : r;
}

static int fail(const nbrdf_error *err) {
  fprintf(stderr, "bench_audit_margin: %s\n", err->message);
  return 1;
}

static double brute_max(const nbrdf_model *model, model_runner *runner, const float *lat,
                        const float *sig, nbrdf_error *err) {
  double rho[BAKE_AUDIT_N_THETA], m = -1.0;
  if (model_albedo_decoded(model->decoder, runner, 1, lat, sig, BAKE_AUDIT_N_THETA,
                           bake_audit_theta_deg, 16384, UINT64_C(0x62727574), rho, NULL,
                           err) != NBRDF_OK)
    return NAN;
  for (int a = 0; a < BAKE_AUDIT_N_THETA; a++)
    m = fmax(m, rho[a]);
  return m;
}

/* The indices of the k largest of v[n] into top[k] (k <= n), largest first. */
static void largest(const double *v, size_t n, size_t k, size_t *top) {
  for (size_t j = 0; j < k; j++) {
    size_t best = (size_t)-1;
    for (size_t i = 0; i < n; i++) {
      int taken = 0;
      for (size_t q = 0; q < j; q++)
        taken |= top[q] == i;
      if (!taken && (best == (size_t)-1 || v[i] > v[best])) best = i;
    }
    top[j] = best;
  }
}

static int texture(const nbrdf_model *model, const char *file, int k) {
  nbrdf_error err = {0};
  texture_latent_reader *r = NULL;
  if (texture_latent_reader_open(&r, file, &err) != NBRDF_OK) return fail(&err);
  const texture_latent_info *info = texture_latent_reader_info(r);
  const int C = texture_latent_colours(&info->layout), D = info->layout.latent_dim;
  const size_t texels = (size_t)info->width * info->height, n = texels * C;
  float *tex = malloc(texels * info->channels * sizeof *tex);
  float *lat = malloc(n * D * sizeof *lat), *sig = malloc(n * sizeof *sig);
  double *now = malloc(n * sizeof *now), *old = malloc(n * sizeof *old);
  if (texture_latent_reader_read(r, 0, 0, 0, info->width, info->height, tex, &err) != NBRDF_OK)
    return fail(&err);
  for (size_t i = 0; i < texels; i++)
    for (int c = 0; c < C; c++) {
      for (int j = 0; j < D; j++)
        lat[(i * C + c) * D + j] =
            tex[i * info->channels + texture_latent_index_latent(&info->layout, c, j)];
      sig[i * C + c] = tex[i * info->channels + texture_latent_index_sigma(&info->layout, c)];
    }
  double c0 = bench_cpu_seconds();
  if (bake_albedo_precise(model, NULL, n, lat, sig, now, NULL, &err) != NBRDF_OK)
    return fail(&err);
  double c1 = bench_cpu_seconds();
  if (bake_albedo_max(model, n, lat, sig, old, NULL, &err) != NBRDF_OK) return fail(&err);
  double c2 = bench_cpu_seconds();
  if ((size_t)k > n) k = (int)n;
  size_t *top = malloc(2 * (size_t)k * sizeof *top);
  largest(now, n, (size_t)k, top);
  largest(old, n, (size_t)k, top + k);
  model_runner runner;
  if (model_runner_create(model->decoder->nn, 4096, NBRDF_NN_INFER, &runner, &err) != NBRDF_OK)
    return fail(&err);
  double brute = -1.0;
  for (int j = 0; j < 2 * k; j++)
    brute = fmax(brute, brute_max(model, &runner, lat + top[j] * D, sig + top[j], &err));
  model_runner_destroy(&runner);
  printf("%s: %zu latents; header nbrdf:maxAlbedo %.4f\n", file, n, (double)info->max_albedo);
  printf("every latent, audit's quadrature: max %.4f (%.2f CPU-s); old audit's: max %.4f "
         "(%.2f CPU-s)\n",
         now[top[0]], c1 - c0, old[top[k]], c2 - c1);
  printf("brute force (16,384 directions) of the %d largest of each: max %.4f\n", k, brute);
  free(tex), free(lat), free(sig), free(now), free(old), free(top);
  texture_latent_reader_close(r);
  return 0;
}

int main(int argc, char **argv) {
  const char *bundle = NULL, *file = NULL;
  int bases = 24, sharp = 0, k_top = 8, no_brute = 0;
  double noise = BAKE_AUDIT_NOISE;
  unsigned long long seed = 11;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--bundle") && i + 1 < argc)
      bundle = argv[++i];
    else if (!strcmp(argv[i], "--bases") && i + 1 < argc)
      bases = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--sharp"))
      sharp = 1;
    else if (!strcmp(argv[i], "--no-brute"))
      no_brute = 1;
    else if (!strcmp(argv[i], "--noise") && i + 1 < argc)
      noise = atof(argv[++i]);
    else if (!strcmp(argv[i], "--seed") && i + 1 < argc)
      seed = strtoull(argv[++i], NULL, 10);
    else if (!strcmp(argv[i], "--texture") && i + 1 < argc)
      file = argv[++i];
    else if (!strcmp(argv[i], "--top") && i + 1 < argc)
      k_top = atoi(argv[++i]);
  }
  nbrdf_error err = {0};
  nbrdf_model *model = NULL;
  if ((bundle ? nbrdf_model_load(bundle, &model, &err)
              : nbrdf_model_load_default(&model, NULL, 0, &err)) != NBRDF_OK)
    return fail(&err);
  if (file) {
    int rc = texture(model, file, k_top);
    nbrdf_model_destroy(model);
    return rc;
  }
  float lo[P], hi[P];
  model_material_ranges(model, lo, hi);
  const int D = nbrdf_model_latent_dim(model);
  /* per base: the base, N_STEP steps along each parameter, one cell member */
  enum { N_STEP = 4 };
  static const double step[N_STEP] = {1.0 / 32, 1.0 / 16, 1.0 / 8, 1.0 / 4};
  const int per = N_STEP * P + 2;
  const size_t n = (size_t)bases * per;
  bake_tuple *t = calloc(n, sizeof *t);
  double *u = calloc(n * P, sizeof *u);
  float *out = malloc(n * (D + 2) * sizeof *out);
  float *lat = malloc(n * D * sizeof *lat), *sig = malloc(n * sizeof *sig);
  double *mx = malloc(n * sizeof *mx), *brute = malloc(bases * sizeof *brute);
  double *rho = malloc(bases * BAKE_AUDIT_N_THETA * sizeof *rho);
  const double cell = 1.0 / BAKE_AUDIT_GRID;
  core_rng rng;
  core_rng_init(&rng, seed, sharp);
  for (int b = 0; b < bases; b++) {
    double *ub = u + (size_t)b * per * P;
    for (int id = 0; id < P; id++)
      ub[id] = core_rng_uniform(&rng);
    /* stratified over the slope regions of (alpha1, alpha2) */
    ub[NBRDF_BAKE_ALPHA1] = (b % R + ub[NBRDF_BAKE_ALPHA1]) / R;
    ub[NBRDF_BAKE_ALPHA2] = (b / R % R + ub[NBRDF_BAKE_ALPHA2]) / R;
    if (sharp) {
      ub[NBRDF_BAKE_ALPHA1] = 0.0;
      ub[NBRDF_BAKE_ETA] = model_material_normalise(lo, hi, NBRDF_BAKE_ETA, 1.45f);
      ub[NBRDF_BAKE_ALBEDO] = model_material_normalise(lo, hi, NBRDF_BAKE_ALBEDO, 0.8f);
      ub[NBRDF_BAKE_SIGMA_T] = model_material_normalise(lo, hi, NBRDF_BAKE_SIGMA_T, 1.0f);
      ub[NBRDF_BAKE_R0] = 0.5 + 0.5 * ub[NBRDF_BAKE_R0];
    }
    for (int s = 1; s < per; s++) {
      double *us = ub + (size_t)s * P;
      memcpy(us, ub, P * sizeof *us);
      if (s <= N_STEP * P) { /* a step along one parameter, inward */
        int id = (s - 1) / N_STEP;
        double h = step[(s - 1) % N_STEP];
        us[id] += us[id] + h <= 1.0 ? h : -h;
      } else { /* a tuple of the base's cell (base: its representative) */
        for (int id = 0; id < P; id++) {
          if (sharp && id != NBRDF_BAKE_ALPHA2 && id != NBRDF_BAKE_R0) continue;
          int q = (int)(ub[id] * BAKE_AUDIT_GRID);
          q = q >= BAKE_AUDIT_GRID ? BAKE_AUDIT_GRID - 1 : q;
          us[id] = (q + core_rng_uniform(&rng)) * cell;
        }
      }
    }
  }
  for (size_t k = 0; k < n; k++)
    for (int id = 0; id < P; id++) {
      t[k].p[id] = model_material_unnormalise(lo, hi, id, u[k * P + id]);
      u[k * P + id] = model_material_normalise(lo, hi, id, t[k].p[id]);
    }
  if (bake_tuples_evaluate(model, t, NULL, n, out, &err) != NBRDF_OK) return fail(&err);
  for (size_t k = 0; k < n; k++) {
    memcpy(lat + k * D, out + k * (D + 2), D * sizeof *lat);
    sig[k] = out[k * (D + 2) + D];
  }
  double w0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
  if (bake_albedo_precise(model, NULL, n, lat, sig, mx, NULL, &err) != NBRDF_OK) return fail(&err);
  double w1 = bench_wall_seconds(), c1 = bench_cpu_seconds();
  /* brute force on the bases */
  model_runner runner;
  if (model_runner_create(model->decoder->nn, 4096, NBRDF_NN_INFER, &runner, &err) != NBRDF_OK)
    return fail(&err);
  for (int b = 0; b < bases; b++) {
    size_t k = (size_t)b * per;
    if (no_brute) { /* slopes and bounds only: the audit's own value stands in */
      brute[b] = mx[k];
      continue;
    }
    if (model_albedo_decoded(model->decoder, &runner, 1, lat + k * D, sig + k, BAKE_AUDIT_N_THETA,
                             bake_audit_theta_deg, 16384, UINT64_C(0x62727574),
                             rho + (size_t)b * BAKE_AUDIT_N_THETA, NULL, &err) != NBRDF_OK)
      return fail(&err);
    brute[b] = 0.0;
    for (int a = 0; a < BAKE_AUDIT_N_THETA; a++)
      brute[b] = fmax(brute[b], rho[(size_t)b * BAKE_AUDIT_N_THETA + a]);
  }
  model_runner_destroy(&runner);
  size_t at[P] = {0}, at_step[P] = {0};
  static double reg[R][R][P];
  static int seen[R][R];
  double slope[P] = {0}, raw[P] = {0}, under = 0.0, over = 0.0, violation = -INFINITY, top = 0.0;
  for (int b = 0; b < bases; b++) {
    size_t k = (size_t)b * per;
    top = fmax(top, brute[b]);
    under = fmax(under, brute[b] - mx[k]);
    over = fmax(over, mx[k] - brute[b]);
    /* The bound's model: |m(u) - m(a)| <= NOISE + slope |u - a| (m: the audit's
     * measurement, whose error is part of NOISE), so the slope that this pair
     * needs is (|Δm| - NOISE) / |Δu|; raw: |Δm| / |Δu| at the step 1/16. */
    for (int id = 0; id < P; id++)
      if (!sharp || id == NBRDF_BAKE_ALPHA2 || id == NBRDF_BAKE_R0)
        for (int j = 0; j < N_STEP; j++) {
          size_t s = k + 1 + (size_t)id * N_STEP + j;
          double du = fabs(u[s * P + id] - u[k * P + id]), dm = fabs(mx[s] - mx[k]);
          if (!(du > 0.0)) continue;
          double need = (dm - noise) / du;
          if (need > slope[id]) {
            slope[id] = need;
            at[id] = k, at_step[id] = s;
          }
          /* every region the step spans needs it (bake_audit_reach takes the largest) */
          int a0 = region(u[k * P + NBRDF_BAKE_ALPHA1]), a1 = region(u[s * P + NBRDF_BAKE_ALPHA1]);
          int b0 = region(u[k * P + NBRDF_BAKE_ALPHA2]), b1 = region(u[s * P + NBRDF_BAKE_ALPHA2]);
          for (int a = a0 < a1 ? a0 : a1; a <= (a0 < a1 ? a1 : a0); a++)
            for (int c = b0 < b1 ? b0 : b1; c <= (b0 < b1 ? b1 : b0); c++)
              reg[a][c][id] = fmax(reg[a][c][id], need), seen[a][c] = 1;
          if (step[j] == 1.0 / 16) raw[id] = fmax(raw[id], dm / du);
        }
    size_t m = k + N_STEP * P + 1;
    float fu[P], fv[P];
    for (int id = 0; id < P; id++)
      fu[id] = (float)u[m * P + id], fv[id] = (float)u[k * P + id];
    double bound = mx[k] + BAKE_AUDIT_NOISE + bake_audit_reach(fu, fv);
    violation = fmax(violation, mx[m] - bound);
  }
  printf("%d bases (%s), %zu latents, audit quadrature %.2f CPU-s (%.2f wall) = %.0f "
         "latents/CPU-s\n",
         bases, sharp ? "sharp clearcoat" : "whole range", n, c1 - c0, w1 - w0,
         (double)n / (c1 - c0));
  printf("largest brute-force albedo %.4f; audit minus brute force: down %.4f, up %.4f "
         "(BAKE_AUDIT_NOISE %.3f)\n",
         top, under, over, BAKE_AUDIT_NOISE);
  printf("largest |change| per unit normalised parameter at the step 1/16:");
  for (int id = 0; id < P; id++)
    printf(" %s %.3f", nbrdf_bake_param_name((nbrdf_bake_param_id)id), raw[id]);
  printf("\nslope the bound needs, (|change| - noise %.3f) / step, steps 1/32 to 1/4:", noise);
  for (int id = 0; id < P; id++)
    printf(" %s %.3f", nbrdf_bake_param_name((nbrdf_bake_param_id)id), slope[id]);
  printf("\nwhere (the base's alpha1 eta alpha2 r0 albedo sigma_t -> its value, the step's value):\n");
  for (int id = 0; id < P; id++) {
    if (!(slope[id] > 0.0)) continue;
    printf("  %s:", nbrdf_bake_param_name((nbrdf_bake_param_id)id));
    for (int j = 0; j < P; j++)
      printf(" %g", (double)t[at[id]].p[j]);
    printf(" -> %.4f; step to %g -> %.4f\n", mx[at[id]], (double)t[at_step[id]].p[id],
           mx[at_step[id]]);
  }
  printf("bake_audit_slope, largest of the regions:");
  double smax[P];
  bake_audit_slope_max(smax);
  for (int id = 0; id < P; id++)
    printf(" %.3f", smax[id]);
  /* The table for src/bake/bake_audit_slopes.inc: each region's need times 1.5, at
   * least a third of the parameter's largest need over all regions (64 bases per
   * region miss steeper spots: with 1.25 and no floor a random cell member of another
   * draw exceeded its bound by 0.017); a region no step reached gets the largest. */
  printf("\nper region (alpha1 bin, alpha2 bin), need x 1.5, at least the largest / 3:\n");
  for (int a = 0; a < R; a++) {
    printf("  {");
    for (int c = 0; c < R; c++) {
      printf("{");
      for (int id = 0; id < P; id++) {
        double v = seen[a][c] ? fmax(reg[a][c][id], slope[id] / 3.0) : slope[id];
        printf("%.2f%s", fmax(0.25, ceil(150.0 * v) / 100.0), id + 1 < P ? ", " : "");
      }
      printf("}%s", c + 1 < R ? ", " : "");
    }
    printf("}%s\n", a + 1 < R ? "," : "");
  }
  printf("\nlargest cell member minus its bound: %.4f (must be <= 0)\n", violation);
  free(t), free(u), free(out), free(lat), free(sig), free(mx), free(brute), free(rho);
  nbrdf_model_destroy(model);
  return 0;
}
