/* The energy audit's bound (src/bake/bake_audit.h): how fast the decoded
 * albedo moves per unit of normalised parameter (the measurement of `nbrdf bundle
 * audit-slopes`, bake_audit_slopes.h), how far the audit's quadrature is from a
 * brute-force one (BAKE_AUDIT_NOISE), and whether representative + the bundle's
 * slopes + noise really bounds the tuples of a cell (another --seed than the
 * bundle's table was measured with checks it on a new draw).
 *
 *   bench_audit_margin [--bundle DIR] [--bases N] [--sharp] [--no-brute]
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
#include "bake/bake_audit_slopes.h"
#include "bake/bake_tuple.h"
#include "bench_clock.h"
#include "model/albedo_quad.h"
#include "model/audit_slopes.h"
#include "model/bundle.h"
#include "model/material.h"
#include "model/netio.h"
#include "nbrdf/bake.h"
#include "texture/latent_exr.h"

enum { P = NBRDF_BAKE_PARAM_COUNT, R = BAKE_AUDIT_REGIONS };

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
  if (bake_albedo_precise(model, NULL, n, lat, sig, now, NULL, &err) != NBRDF_OK) return fail(&err);
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
  /* The library's measurement (bake_audit_slopes.h): the table `nbrdf bundle
   * audit-slopes` would record, and every tuple it measured. */
  bake_audit_slopes_options so = BAKE_AUDIT_SLOPES_OPTIONS_DEFAULT;
  so.bases = sharp ? 0 : bases, so.sharp_bases = sharp ? bases : 0, so.seed = seed;
  static double table[R * R * P * BAKE_AUDIT_DIRS];
  bake_audit_slopes_draws d;
  double w0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
  if (bake_audit_slopes_measure(model, &so, table, &d, &err) != NBRDF_OK) return fail(&err);
  double w1 = bench_wall_seconds(), c1 = bench_cpu_seconds();
  const int D = nbrdf_model_latent_dim(model), per = d.per;
  const size_t n = d.n_bases * (size_t)per;
  const double *u = d.u, *mx = d.value;
  const bake_tuple *t = d.t;
  double *brute = malloc(d.n_bases * sizeof *brute);
  double *rho = malloc(d.n_bases * BAKE_AUDIT_N_THETA * sizeof *rho);
  /* The bundle's own slopes, against which the cell members are checked (none: the
   * table just measured). */
  const double *slopes = model_audit_slopes(model) ? model_audit_slopes(model) : table;
  /* brute force on the bases */
  model_runner runner;
  if (model_runner_create(model->decoder->nn, 4096, NBRDF_NN_INFER, &runner, &err) != NBRDF_OK)
    return fail(&err);
  for (size_t b = 0; b < d.n_bases; b++) {
    size_t k = b * per;
    if (no_brute) { /* slopes and bounds only: the audit's own value stands in */
      brute[b] = mx[k];
      continue;
    }
    if (model_albedo_decoded(model->decoder, &runner, 1, d.lat + k * D, d.sigma + k,
                             BAKE_AUDIT_N_THETA, bake_audit_theta_deg, 16384, UINT64_C(0x62727574),
                             rho + b * BAKE_AUDIT_N_THETA, NULL, &err) != NBRDF_OK)
      return fail(&err);
    brute[b] = 0.0;
    for (int a = 0; a < BAKE_AUDIT_N_THETA; a++)
      brute[b] = fmax(brute[b], rho[b * BAKE_AUDIT_N_THETA + a]);
  }
  model_runner_destroy(&runner);
  double raw[P] = {0}, under = 0.0, over = 0.0, violation = -INFINITY, top = 0.0;
  size_t above = 0, worst_member = 0, worst_base = 0, missed = 0, above_of[P] = {0};
  double excess_of[P] = {0};
  for (size_t b = 0; b < d.n_bases; b++) {
    size_t k = b * per;
    top = fmax(top, brute[b]);
    under = fmax(under, brute[b] - mx[k]);
    over = fmax(over, mx[k] - brute[b]);
    /* raw: |Δm| / |Δu| at the step 1/16 */
    for (int id = 0; id < P; id++) {
      size_t s = k + 1 + (size_t)id * BAKE_AUDIT_SLOPES_STEPS + 1;
      double du = fabs(u[s * P + id] - u[k * P + id]);
      if (du > 0.0) raw[id] = fmax(raw[id], fabs(mx[s] - mx[k]) / du);
    }
    size_t m = k + BAKE_AUDIT_SLOPES_STEPS * P + 1;
    float fu[P], fv[P];
    for (int id = 0; id < P; id++)
      fu[id] = (float)u[m * P + id], fv[id] = (float)u[k * P + id];
    double bound = mx[k] + BAKE_AUDIT_NOISE + bake_audit_reach(slopes, fu, fv);
    if (mx[m] - bound > violation) violation = mx[m] - bound, worst_member = m, worst_base = k;
    /* what the audit would get wrong: a member its base clears that is above the limit */
    missed += bound <= BAKE_AUDIT_LIMIT && mx[m] > BAKE_AUDIT_LIMIT;
    /* single steps that need more than the bundle's table gives them */
    for (int s = 1; s <= BAKE_AUDIT_SLOPES_STEPS * P; s++) {
      size_t ks = k + (size_t)s;
      float a[P], c[P];
      for (int j = 0; j < P; j++)
        a[j] = (float)u[ks * P + j], c[j] = (float)u[k * P + j];
      /* a rise from the base to the step, or from the step back to the base */
      double ex = fmax(mx[ks] - mx[k] - BAKE_AUDIT_NOISE - bake_audit_reach(slopes, a, c),
                       mx[k] - mx[ks] - BAKE_AUDIT_NOISE - bake_audit_reach(slopes, c, a));
      if (ex > 1e-12) {
        int id = (s - 1) / BAKE_AUDIT_SLOPES_STEPS;
        above++, above_of[id]++, excess_of[id] = fmax(excess_of[id], ex);
      }
    }
  }
  printf("%zu bases (%s), %zu latents, measured in %.2f CPU-s (%.2f wall) = %.0f latents/CPU-s\n",
         d.n_bases, sharp ? "sharp clearcoat" : "whole range", n, c1 - c0, w1 - w0,
         (double)n / (c1 - c0));
  printf("largest brute-force albedo %.4f; audit minus brute force: down %.4f, up %.4f "
         "(BAKE_AUDIT_NOISE %.3f)\n",
         top, under, over, BAKE_AUDIT_NOISE);
  printf("largest |change| per unit normalised parameter at the step 1/16:");
  for (int id = 0; id < P; id++)
    printf(" %s %.3f", nbrdf_bake_param_name((nbrdf_bake_param_id)id), raw[id]);
  printf("\nslope the bound needs, (|change| - noise %.3f) / step, steps 1/32 to 1/4:",
         BAKE_AUDIT_NOISE);
  for (int id = 0; id < P; id++)
    printf(" %s %.3f", nbrdf_bake_param_name((nbrdf_bake_param_id)id), d.need[id]);
  printf(
      "\nwhere (the base's alpha1 eta alpha2 r0 albedo sigma_t -> its value, the step's value):\n");
  for (int id = 0; id < P; id++) {
    if (!(d.need[id] > 0.0)) continue;
    printf("  %s:", nbrdf_bake_param_name((nbrdf_bake_param_id)id));
    for (int j = 0; j < P; j++)
      printf(" %g", (double)t[d.need_at[id]].p[j]);
    printf(" -> %.4f; step to %g -> %.4f\n", mx[d.need_at[id]], (double)t[d.need_step[id]].p[id],
           mx[d.need_step[id]]);
  }
  double smax[P];
  bake_audit_slope_max(model_audit_slopes(model), smax);
  printf("the bundle's audit slopes (%s), largest of the regions:",
         model_audit_slopes(model) ? "model.json" : "none");
  for (int id = 0; id < P; id++)
    printf(" %.3f", smax[id]);
  printf("\nsteps whose change exceeds noise + the bundle's reach: %zu of %zu; per parameter "
         "(count, largest excess):",
         above, d.n_bases * BAKE_AUDIT_SLOPES_STEPS * P);
  for (int id = 0; id < P; id++)
    printf(" %s %zu %.3f", nbrdf_bake_param_name((nbrdf_bake_param_id)id), above_of[id],
           excess_of[id]);
  printf("\n");
  printf("the table `nbrdf bundle audit-slopes` would record from these draws (alpha1 bin, "
         "alpha2 bin; up/down per parameter):\n");
  for (int a = 0; a < R; a++) {
    printf("  {");
    for (int c = 0; c < R; c++) {
      printf("{");
      for (int id = 0; id < P; id++) {
        const double *e = table + (((size_t)a * R + c) * P + (size_t)id) * BAKE_AUDIT_DIRS;
        printf("%.2f/%.2f%s", e[0], e[1], id + 1 < P ? ", " : "");
      }
      printf("}%s", c + 1 < R ? ", " : "");
    }
    printf("}%s\n", a + 1 < R ? "," : "");
  }
  printf("\nlargest cell member minus its bound (the %s slopes): %.4f (must be <= 0)\n",
         model_audit_slopes(model) ? "bundle's" : "measured", violation);
  printf("  the member:");
  for (int j = 0; j < P; j++)
    printf(" %g", (double)t[worst_member].p[j]);
  printf(" -> %.4f; its base:", mx[worst_member]);
  for (int j = 0; j < P; j++)
    printf(" %g", (double)t[worst_base].p[j]);
  printf(" -> %.4f\n", mx[worst_base]);
  printf("cell members above %.2f that their base's bound clears (the audit would miss them): "
         "%zu of %zu\n",
         BAKE_AUDIT_LIMIT, missed, d.n_bases);
  free(brute), free(rho);
  bake_audit_slopes_draws_free(&d);
  nbrdf_model_destroy(model);
  return 0;
}
