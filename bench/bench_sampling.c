/* Importance sampling of neural BRDFs (issue 5, the paper's Fig. 6): the
 * variance of estimating reflected radiance under an environment with the
 * Eq. 6 proxy of the sampling network, cosine-weighted hemisphere sampling,
 * sampling the top layer's GGX, and one-sample MIS of proxy and cosine, at
 * equal sample counts, for the held-out two-layer BRDFs of the `layer` set
 * obtained as a bake obtains them (base tables + layering network), decoded by
 * the bundle's decoder. src/bench/support/radiance_variance.h has the estimators.
 * docs/SAMPLING_AND_COST.md has the figures and the command. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "render/env.h"
#include "support/plot.h"
#include "support/radiance_variance.h"
#include "nbrdf/model.h"
#include "nbrdf/render.h"
#include "train/params.h"

#include "bench_args.h"
#include "bench_clock.h"
#include "bench_sort.h"

enum { N_THETA = 4, N_PHI = 2, MAX_CASES = N_THETA * N_PHI, N_ENV = 2 };
static const double THETA_O[N_THETA] = {0.0, 30.0, 60.0, 80.0};
static const char *const ENV_NAMES[N_ENV] = {"sky", "furnace"};

typedef struct config {
  const char *bundle, *out, *plot_prefix;
  int count, reps, n_counts, counts[BENCH_IS_MAX_N], envs; /* envs: bit 0 sky, bit 1 furnace */
  int swap; /* integrate over the decoder's ωo slot instead (a check of reciprocity) */
} config;

static void usage(FILE *f) {
  fprintf(f,
          "usage: bench_sampling [--bundle models/default] [--count 100] [--reps 200]\n"
          "                      [--n 16,64] [--env sky|furnace|both] [--out sampling.md]\n"
          "                      [--plot PREFIX]  (writes PREFIX_variance.png, PREFIX_ratio.png)\n"
          "                      [--integrate-over wi|wo]\n"
          "Variance of the reflected radiance L(wo) of the held-out `layer` BRDFs (tables +\n"
          "layering network, decoded) estimated with N samples by proxy, cosine, top-layer GGX\n"
          "and proxy+cosine MIS sampling, from --reps independent repetitions, at\n"
          "theta_o = 0, 30, 60, 80 deg (the last three with the mirror direction towards the\n"
          "sun's azimuth and away from it). --integrate-over wo swaps the decoder's direction\n"
          "arguments (the integral over its second slot: the usual albedo in a furnace).\n"
          "Run with OPENBLAS_NUM_THREADS=1 on a shared machine.\n");
}

static int parse_args(int argc, char **argv, config *c) {
  *c = (config){"models/default", "sampling.md", "sampling", 100, 200, 2, {16, 64}, 3, 0};
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *v = bench_option_value(argc, argv, &i, "bench_sampling", usage);
    if (!v) return 0;
    if (!strcmp(a, "--bundle")) {
      c->bundle = v;
    } else if (!strcmp(a, "--count")) {
      c->count = atoi(v);
    } else if (!strcmp(a, "--reps")) {
      c->reps = atoi(v);
    } else if (!strcmp(a, "--n")) {
      if (!(c->n_counts = bench_parse_counts(v, c->counts, BENCH_IS_MAX_N, 1, 4096, 0))) {
        fprintf(stderr, "bench_sampling: --n wants 1..%d counts in 1..4096\n", BENCH_IS_MAX_N);
        return 0;
      }
    } else if (!strcmp(a, "--env")) {
      c->envs = !strcmp(v, "sky") ? 1 : !strcmp(v, "furnace") ? 2 : !strcmp(v, "both") ? 3 : 0;
      if (!c->envs) {
        fprintf(stderr, "bench_sampling: --env must be sky, furnace or both\n");
        return 0;
      }
    } else if (!strcmp(a, "--integrate-over")) {
      c->swap = !strcmp(v, "wo");
      if (!c->swap && strcmp(v, "wi")) {
        fprintf(stderr, "bench_sampling: --integrate-over must be wi or wo\n");
        return 0;
      }
    } else if (!strcmp(a, "--out")) {
      c->out = v;
    } else if (!strcmp(a, "--plot")) {
      c->plot_prefix = v;
    } else {
      fprintf(stderr, "bench_sampling: unknown option %s\n", a);
      return 0;
    }
  }
  if (c->count < 1 || c->reps < 2) {
    fprintf(stderr, "bench_sampling: --count must be >= 1 and --reps >= 2\n");
    return 0;
  }
  return 1;
}

static void die(const char *what, const nbrdf_error *err) {
  fprintf(stderr, "bench_sampling: %s: %s\n", what, err->message);
  exit(1);
}

/* ------------------------------------------------------------ the BRDF */

typedef struct neural_brdf {
  const nbrdf_model *m;
  const float *latent;
  int swap;
  size_t cap;
  float *lat, *dirs, *f; /* grown on demand */
} neural_brdf;

static nbrdf_status neural_fn(void *user, size_t n, const nbrdf_query *q, double *f,
                              nbrdf_error *err) {
  neural_brdf *b = user;
  size_t D = (size_t)nbrdf_model_latent_dim(b->m);
  if (n > b->cap) {
    free(b->lat), free(b->dirs), free(b->f);
    b->lat = malloc(n * D * sizeof *b->lat), b->dirs = malloc(6 * n * sizeof *b->dirs);
    b->f = malloc(n * sizeof *b->f);
    b->cap = b->lat && b->dirs && b->f ? n : 0;
    if (!b->cap) return core_fail(err, NBRDF_ERR_MEMORY, "bench_sampling: out of memory");
  }
  for (size_t k = 0; k < n; k++) {
    memcpy(b->lat + k * D, b->latent, D * sizeof *b->lat);
    const double *a = b->swap ? q[k].wo : q[k].wi, *o = b->swap ? q[k].wi : q[k].wo;
    for (int j = 0; j < 3; j++)
      b->dirs[3 * k + j] = (float)a[j], b->dirs[3 * (n + k) + j] = (float)o[j];
  }
  nbrdf_status st = nbrdf_model_decode(b->m, n, 1, b->lat, b->dirs, b->dirs + 3 * n, b->f, err);
  for (size_t k = 0; k < n && !st; k++)
    f[k] = b->f[k];
  return st;
}

/* ------------------------------------------------------------ the light */

/* Shading frame (z up) to the environment's world frame (y up). */
static vec3 to_world(vec3 d) { return v3(d.x, d.z, -d.y); }

static double luminance(const double c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

static double sky_radiance(void *user, vec3 wi) {
  double rgb[3];
  render_env_radiance(user, to_world(wi), rgb);
  return luminance(rgb);
}

static double furnace_radiance(void *user, vec3 wi) {
  (void)user, (void)wi;
  return 1.0;
}

/* Azimuth (shading frame) of the brightest sky direction: the sun. */
static double sun_azimuth(const render_env *env) {
  double best = -1, phi_best = 0;
  for (int i = 0; i < 90; i++)
    for (int j = 0; j < 720; j++) {
      double th = (i + 0.5) * M_PI / 180, ph = (j + 0.5) * M_PI / 360;
      double l = sky_radiance((void *)env, v3_from_spherical(th, ph));
      if (l > best) best = l, phi_best = ph;
    }
  return phi_best;
}

/* ------------------------------------------------------------ statistics */

/* Quantile q of n values (sorted copy; non-finite ones count as +Inf). */
static double quantile(const double *v, int n, double q) {
  double *s = malloc((size_t)n * sizeof *s);
  if (!s || n == 0) {
    free(s);
    return NAN;
  }
  for (int i = 0; i < n; i++)
    s[i] = isfinite(v[i]) ? v[i] : INFINITY;
  qsort(s, (size_t)n, sizeof *s, bench_cmp_double);
  int k = (int)ceil(q * n) - 1;
  double r = s[k < 0 ? 0 : k];
  free(s);
  return r;
}

typedef struct case_result {
  int brdf, theta, toward_sun;
  bench_is_result r;
} case_result;

/* Relative variance var / L² of strategy s at count index k. */
static double relvar(const case_result *c, int s, int k) {
  double L = c->r.radiance;
  return L > 0 ? c->r.var[s][k] / (L * L) : NAN;
}

/* ------------------------------------------------------------ main */

int main(int argc, char **argv) {
  config c;
  if (!parse_args(argc, argv, &c)) {
    usage(stderr);
    return 2;
  }
  nbrdf_error err = {0};
  nbrdf_model *m = NULL;
  if (nbrdf_model_load(c.bundle, &m, &err)) die("loading the bundle", &err);
  const size_t n = (size_t)c.count, D = (size_t)nbrdf_model_latent_dim(m);
  const double load0 = bench_load_average(), t0 = bench_wall_seconds(), cpu0 = bench_cpu_seconds();

  /* The held-out `layer` BRDFs, as nbrdf evaluate and a bake obtain them. */
  train_params *p = malloc(n * sizeof *p);
  float *a1 = malloc(4 * n * sizeof *a1), *eta = a1 + n, *a2 = a1 + 2 * n, *r0 = a1 + 3 * n;
  float *top = malloc(3 * n * D * sizeof *top), *bottom = top + n * D, *lat = top + 2 * n * D;
  float *albedo = malloc(4 * n * sizeof *albedo), *sigma_t = albedo + n, *sigma = albedo + 2 * n,
        *w = albedo + 3 * n;
  if (!p || !a1 || !top || !albedo) return 1;
  const uint64_t family = train_heldout_seed(TRAIN_HELDOUT_LAYER);
  for (size_t i = 0; i < n; i++) {
    train_params_draw(family, train_heldout_kind(TRAIN_HELDOUT_LAYER), i, &p[i]);
    a1[i] = (float)p[i].coat[0].alpha, eta[i] = (float)p[i].coat[0].eta;
    a2[i] = (float)p[i].base_alpha, r0[i] = (float)p[i].base_r0;
    albedo[i] = (float)p[i].coat[0].albedo, sigma_t[i] = (float)p[i].coat[0].sigma_t;
  }
  if (nbrdf_model_base_latents(m, NBRDF_BASE_DIELECTRIC, n, a1, eta, NBRDF_RANGE_CLAMP, top, NULL,
                               &err) ||
      nbrdf_model_base_latents(m, NBRDF_BASE_CONDUCTOR, n, a2, r0, NBRDF_RANGE_CLAMP, bottom, NULL,
                               &err) ||
      nbrdf_model_layer(m, n, top, bottom, albedo, sigma_t, lat, &err) ||
      nbrdf_model_proxy_params(m, n, lat, sigma, w, &err))
    die("latents", &err);

  nbrdf_render_options ro = NBRDF_RENDER_OPTIONS_DEFAULT;
  render_env *sky = NULL;
  if (render_env_create(&ro, &sky, &err)) die("sky", &err);
  const double phi_sun = sun_azimuth(sky);

  int n_cases = 0;
  case_result *cases[N_ENV] = {NULL, NULL};
  neural_brdf nb = {m, NULL, c.swap, 0, NULL, NULL, NULL};
  for (int e = 0; e < N_ENV; e++) {
    if (!(c.envs & (1 << e))) continue;
    cases[e] = calloc(n * MAX_CASES, sizeof **cases);
    if (!cases[e]) return 1;
    bench_is_setup su = {neural_fn,
                         &nb,
                         e == 0 ? sky_radiance : furnace_radiance,
                         sky,
                         c.reps,
                         c.n_counts,
                         {0},
                         0x5a3b1e + (uint64_t)e};
    memcpy(su.counts, c.counts, sizeof su.counts);
    n_cases = 0;
    for (size_t i = 0; i < n; i++) {
      nb.latent = lat + i * D;
      bench_is_lobe lobe = {sigma[i], w[i], p[i].coat[0].alpha};
      for (int t = 0; t < N_THETA; t++)
        for (int s = 0; s < (THETA_O[t] > 0 ? N_PHI : 1); s++) {
          /* Toward the sun: the mirror direction of ωo (azimuth φo + π) has the sun's azimuth. */
          double phi = s == 0 ? phi_sun + M_PI : phi_sun;
          vec3 wo = v3_from_spherical(THETA_O[t] * M_PI / 180, phi);
          case_result *cr = &cases[e][n_cases];
          cr->brdf = (int)i, cr->theta = t, cr->toward_sun = s == 0;
          if (bench_is_variance(&su, &lobe, wo, (uint64_t)n_cases, &cr->r, &err))
            die("variance", &err);
          n_cases++;
        }
      if ((i + 1) % 10 == 0)
        fprintf(stderr, "  %s: %zu/%zu BRDFs, %.0f s\n", ENV_NAMES[e], i + 1, n,
                bench_wall_seconds() - t0);
    }
  }
  const double wall = bench_wall_seconds() - t0, cpu = bench_cpu_seconds() - cpu0;

  FILE *out = fopen(c.out, "w");
  if (!out) {
    fprintf(stderr, "bench_sampling: cannot write %s\n", c.out);
    return 1;
  }
  FILE *streams[2] = {stdout, out};
  const int K = c.n_counts - 1; /* the largest N is the last given */
  for (int o = 0; o < 2; o++) {
    FILE *f = streams[o];
    fprintf(f,
            "Bundle `%s` (%s, checksum %s); %d held-out `layer` BRDFs x %d outgoing directions; "
            "%d repetitions per estimate; sun azimuth %.1f deg (shading frame); integrated over "
            "the decoder's %s. Wall %.0f s, CPU %.0f s; load average %.2f at the start, %.2f at "
            "the end (shared 2-core machine).\n\n",
            c.bundle, nbrdf_model_name(m), nbrdf_model_checksum(m), c.count, n_cases / c.count,
            c.reps, phi_sun * 180 / M_PI, c.swap ? "wo" : "wi", wall, cpu, load0,
            bench_load_average());
    for (int e = 0; e < N_ENV; e++) {
      if (!cases[e]) continue;
      fprintf(f, "### %s\n\n",
              e == 0 ? "Sky (src/render/env.c, luminance)" : "White furnace (L = 1)");
      fprintf(f, "| N | strategy | median var/L^2 | 90th pct var/L^2 | lost draws | proxy "
                 "variance lower on |\n|---:|---|---:|---:|---:|---:|\n");
      double *v = malloc((size_t)n_cases * sizeof *v);
      for (int k = 0; k < c.n_counts && v; k++)
        for (int s = 0; s < BENCH_IS_COUNT; s++) {
          double lost = 0;
          int wins = 0, valid = 0;
          for (int i = 0; i < n_cases; i++) {
            const case_result *cr = &cases[e][i];
            v[i] = relvar(cr, s, k);
            lost += cr->r.lost[s] / n_cases;
            if (cr->r.radiance > 0) valid++, wins += cr->r.var[BENCH_IS_PROXY][k] < cr->r.var[s][k];
          }
          char share[32] = "-";
          if (s != BENCH_IS_PROXY) snprintf(share, sizeof share, "%.1f %%", 100.0 * wins / valid);
          fprintf(f, "| %d | %s | %.3g | %.3g | %.1f %% | %s |\n", c.counts[k],
                  bench_is_strategy_name((bench_is_strategy)s), quantile(v, n_cases, 0.5),
                  quantile(v, n_cases, 0.9), 100 * lost, share);
        }
      fprintf(f,
              "\nBy outgoing direction, N = %d (median var/L^2; share of BRDFs where the proxy "
              "variance is lower):\n\n| theta_o | mirror | proxy | cosine | ggx | MIS | proxy < "
              "cosine | proxy < ggx |\n|---:|---|---:|---:|---:|---:|---:|---:|\n",
              c.counts[K]);
      for (int t = 0; t < N_THETA && v; t++)
        for (int s = 1; s >= (THETA_O[t] > 0 ? 0 : 1); s--) {
          double med[BENCH_IS_COUNT];
          int nv = 0, win_c = 0, win_g = 0;
          for (int st = 0; st < BENCH_IS_COUNT; st++) {
            nv = 0;
            for (int i = 0; i < n_cases; i++) {
              const case_result *cr = &cases[e][i];
              if (cr->theta != t || (THETA_O[t] > 0 && cr->toward_sun != s)) continue;
              v[nv++] = relvar(cr, st, K);
              if (st == 0) {
                win_c += cr->r.var[0][K] < cr->r.var[BENCH_IS_COSINE][K];
                win_g += cr->r.var[0][K] < cr->r.var[BENCH_IS_GGX][K];
              }
            }
            med[st] = quantile(v, nv, 0.5);
          }
          fprintf(f, "| %.0f | %s | %.3g | %.3g | %.3g | %.3g | %.0f %% | %.0f %% |\n", THETA_O[t],
                  THETA_O[t] == 0 ? "-" : (s ? "towards sun" : "away from sun"), med[0], med[1],
                  med[2], med[3], 100.0 * win_c / nv, 100.0 * win_g / nv);
        }
      if (e == 1) {
        /* In a white furnace L(ωo) is the BRDF's albedo over ωi: above 1 beyond its error,
         * the decoded BRDF creates energy (METRICS.md, "Energy"). */
        int over = 0, worst = 0;
        for (int i = 0; i < n_cases; i++) {
          const bench_is_result *r = &cases[e][i].r;
          double se = sqrt(r->var[BENCH_IS_PROXY][K] / c.reps);
          over += r->radiance > 1.0 + 3.0 * se;
          if (r->radiance > cases[e][worst].r.radiance) worst = i;
        }
        const bench_is_result *r = &cases[e][worst].r;
        const train_params *q = &p[cases[e][worst].brdf];
        fprintf(f,
                "\nEnergy: L > 1 (beyond 3 standard errors) on %d of %d cases; the largest, "
                "L = %.3g, at theta_o = %.0f for BRDF #%d (%.3f, %.2f, %.3f, %.2f, %.2f, %.0f); "
                "the strategies' means there: proxy %.3g, cosine %.3g, ggx %.3g, MIS %.3g.\n",
                over, n_cases, r->radiance, THETA_O[cases[e][worst].theta], cases[e][worst].brdf,
                q->coat[0].alpha, q->coat[0].eta, q->base_alpha, q->base_r0, q->coat[0].albedo,
                q->coat[0].sigma_t, r->mean[0], r->mean[1], r->mean[2], r->mean[3]);
      }
      /* The cases where the proxy loses most against cosine sampling. */
      fprintf(f,
              "\nWorst proxy/cosine variance ratios (N = %d):\n\n| ratio | theta_o | BRDF "
              "(alpha1, eta, alpha2, R0, A, sigma_T) | proxy (sigma, w) | L |\n"
              "|---:|---:|---|---|---:|\n",
              c.counts[K]);
      for (int i = 0; i < n_cases && v; i++)
        v[i] = cases[e][i].r.var[0][K] / cases[e][i].r.var[BENCH_IS_COSINE][K];
      for (int rank = 0; rank < 3 && v; rank++) {
        int worst = -1;
        for (int i = 0; i < n_cases; i++)
          if (isfinite(v[i]) && (worst < 0 || v[i] > v[worst])) worst = i;
        if (worst < 0) break;
        const case_result *cr = &cases[e][worst];
        const train_params *q = &p[cr->brdf];
        fprintf(
            f, "| %.3g | %.0f | #%d (%.3f, %.2f, %.3f, %.2f, %.2f, %.0f) | (%.3f, %.2f) | %.3g |\n",
            v[worst], THETA_O[cr->theta], cr->brdf, q->coat[0].alpha, q->coat[0].eta, q->base_alpha,
            q->base_r0, q->coat[0].albedo, q->coat[0].sigma_t, (double)sigma[cr->brdf],
            (double)w[cr->brdf], cr->r.radiance);
        v[worst] = NAN;
      }
      fprintf(f, "\n");
      free(v);
    }
  }
  fclose(out);

  /* Plots: median relative variance against θo (sky solid, furnace dashed), and the
   * sorted proxy/cosine and proxy/GGX variance ratios. */
  double xs[N_THETA], ys[N_ENV][BENCH_IS_COUNT][N_THETA];
  bench_plot_series ser[N_ENV * BENCH_IS_COUNT];
  int ns = 0;
  double *buf = malloc((size_t)n_cases * sizeof *buf);
  if (!buf) return 1;
  for (int e = 0; e < N_ENV; e++) {
    if (!cases[e]) continue;
    for (int s = 0; s < BENCH_IS_COUNT; s++) {
      for (int t = 0; t < N_THETA; t++) {
        int nv = 0;
        xs[t] = THETA_O[t];
        for (int i = 0; i < n_cases; i++)
          if (cases[e][i].theta == t) buf[nv++] = relvar(&cases[e][i], s, K);
        ys[e][s][t] = quantile(buf, nv, 0.5);
      }
      ser[ns++] = (bench_plot_series){e == 0 ? bench_is_strategy_name((bench_is_strategy)s) : NULL,
                                      N_THETA,
                                      xs,
                                      ys[e][s],
                                      e == 1,
                                      s + 1};
    }
  }
  char path[4096];
  char title[128];
  snprintf(title, sizeof title, "Median relative variance, N = %d (sky solid, furnace dashed)",
           c.counts[K]);
  bench_plot_options po = {title, "theta_o (deg)", "median variance / (L * L)", 0, 1, 0, 0};
  snprintf(path, sizeof path, "%s_variance.png", c.plot_prefix);
  if (bench_plot_write_png(path, &po, ns, ser, &err)) die(path, &err);
  int e0 = cases[0] ? 0 : 1;
  double *rx = malloc((size_t)n_cases * sizeof *rx), *ry[2];
  ry[0] = malloc((size_t)n_cases * sizeof *ry[0]), ry[1] = malloc((size_t)n_cases * sizeof *ry[1]);
  if (!rx || !ry[0] || !ry[1]) return 1;
  for (int i = 0; i < n_cases; i++) {
    const bench_is_result *r = &cases[e0][i].r;
    rx[i] = 100.0 * (i + 0.5) / n_cases;
    ry[0][i] = r->var[0][K] / r->var[BENCH_IS_COSINE][K];
    ry[1][i] = r->var[0][K] / r->var[BENCH_IS_GGX][K];
  }
  qsort(ry[0], (size_t)n_cases, sizeof *ry[0], bench_cmp_double);
  qsort(ry[1], (size_t)n_cases, sizeof *ry[1], bench_cmp_double);
  double one[2] = {1, 1}, ends[2] = {0, 100};
  bench_plot_series rs[3] = {{"proxy / cosine", n_cases, rx, ry[0], 0, 0},
                             {"proxy / ggx", n_cases, rx, ry[1], 0, 0},
                             {NULL, 2, ends, one, 1, 0}};
  snprintf(title, sizeof title, "Variance ratios, %s, N = %d, sorted", ENV_NAMES[e0], c.counts[K]);
  bench_plot_options pr = {
      title, "share of BRDF x direction cases (%)", "proxy variance / other", 0, 1, 0, 0};
  snprintf(path, sizeof path, "%s_ratio.png", c.plot_prefix);
  if (bench_plot_write_png(path, &pr, 3, rs, &err)) die(path, &err);
  fprintf(stderr, "wrote %s, %s_variance.png and %s_ratio.png\n", c.out, c.plot_prefix,
          c.plot_prefix);

  free(buf), free(rx), free(ry[0]), free(ry[1]);
  for (int e = 0; e < N_ENV; e++)
    free(cases[e]);
  free(nb.lat), free(nb.dirs), free(nb.f);
  free(p), free(a1), free(top), free(albedo);
  render_env_free(sky);
  nbrdf_model_destroy(m);
  return 0;
}
