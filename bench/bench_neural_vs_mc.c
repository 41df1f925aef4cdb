/* The paper's central claim, measured (issue 5, "Speed/accuracy"): for the
 * held-out `layer` BRDFs, the lobe error (METRICS.md) and CPU cost per query
 * of (a) the neural path — base-table look-ups and the layering network once
 * per BRDF, the decoder per query — and (b) the Monte Carlo ground truth
 * evaluated per query (nbrdf_brdf_eval) at increasing walks per query, both
 * against the cached whole-lobe references of `nbrdf evaluate`. Then the walks
 * per query the Monte Carlo estimator needs to match the neural error, and the
 * cost ratio at that equal error. One thread throughout (OpenBLAS and the
 * walks), CPU time. docs/SAMPLING_AND_COST.md has the figures and the command. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error.h"
#include "core/rng.h"
#include "lobe/lobe.h"
#include "support/plot.h"
#include "nbrdf/model.h"
#include "nn/safetensors.h"
#include "train/params.h"

#include "bench_args.h"
#include "bench_clock.h"
#include "bench_sgemm.h"
#include "bench_sort.h"

enum { MAX_SPP = 12, PER_BRDF = NBRDF_LOBE_N_THETA * NBRDF_LOBE_RES * NBRDF_LOBE_RES };

typedef struct config {
  const char *bundle, *cache, *out, *plot;
  int ref_count, ref_walks, mc_count, spp[MAX_SPP], n_spp;
  double target; /* a second error level to report the Monte Carlo cost at */
} config;

static void usage(FILE *f) {
  fprintf(f, "usage: bench_neural_vs_mc [--bundle models/default] [--cache data/evalcache]\n"
             "                          [--ref-count 100] [--ref-walks 2000] [--mc-count 20]\n"
             "                          [--spp 1,4,16,64,256] [--target 0.05]\n"
             "                          [--out neural_vs_mc.md] [--plot neural_vs_mc.png]\n"
             "Lobe error and CPU cost per query of the neural path (all --ref-count held-out\n"
             "`layer` BRDFs) and of per-query Monte Carlo evaluation at each spp (the first\n"
             "--mc-count BRDFs, two independent runs each), against the cached references\n"
             "<cache>/ref-layer-n<ref-count>-w<ref-walks>.safetensors of nbrdf evaluate.\n");
}

static int parse_args(int argc, char **argv, config *c) {
  *c = (config){"models/default",
                "data/evalcache",
                "neural_vs_mc.md",
                "neural_vs_mc.png",
                100,
                2000,
                20,
                {1, 4, 16, 64, 256},
                5,
                0.05};
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *v = bench_option_value(argc, argv, &i, "bench_neural_vs_mc", usage);
    if (!v) return 0;
    if (!strcmp(a, "--bundle")) {
      c->bundle = v;
    } else if (!strcmp(a, "--cache")) {
      c->cache = v;
    } else if (!strcmp(a, "--ref-count")) {
      c->ref_count = atoi(v);
    } else if (!strcmp(a, "--ref-walks")) {
      c->ref_walks = atoi(v);
    } else if (!strcmp(a, "--mc-count")) {
      c->mc_count = atoi(v);
    } else if (!strcmp(a, "--target")) {
      c->target = atof(v);
    } else if (!strcmp(a, "--spp")) {
      if (!(c->n_spp = bench_parse_counts(v, c->spp, MAX_SPP, 1, 1L << 30, 1))) {
        fprintf(stderr, "bench_neural_vs_mc: --spp wants up to %d increasing counts >= 1\n",
                MAX_SPP);
        return 0;
      }
    } else if (!strcmp(a, "--out")) {
      c->out = v;
    } else if (!strcmp(a, "--plot")) {
      c->plot = v;
    } else {
      fprintf(stderr, "bench_neural_vs_mc: unknown option %s\n", a);
      return 0;
    }
  }
  if (c->ref_count < 1 || c->ref_walks < 1 || c->mc_count < 1 || c->mc_count > c->ref_count ||
      c->n_spp < 2 || !(c->target > 0)) {
    fprintf(stderr, "bench_neural_vs_mc: need --ref-count, --ref-walks >= 1, 1 <= --mc-count <= "
                    "--ref-count, two or more --spp, --target > 0\n");
    return 0;
  }
  return 1;
}

static void die(const char *what, const nbrdf_error *err) {
  fprintf(stderr, "bench_neural_vs_mc: %s: %s\n", what, err->message);
  exit(1);
}

static double quantile(const double *v, int n, double q) {
  double *s = malloc((size_t)n * sizeof *s);
  if (!s) return NAN;
  memcpy(s, v, (size_t)n * sizeof *s);
  qsort(s, (size_t)n, sizeof *s, bench_cmp_double);
  int k = (int)ceil(q * n) - 1;
  double r = s[k < 0 ? 0 : k];
  free(s);
  return r;
}

/* The references of `nbrdf evaluate` (src/eval/evaluate_reference.c's format). Never
 * recomputed here: they cost hours on this machine. */
static float *load_references(const config *c, double *noise) {
  char path[4096];
  snprintf(path, sizeof path, "%s/ref-layer-n%d-w%d.safetensors", c->cache, c->ref_count,
           c->ref_walks);
  struct stat sb;
  if (stat(path, &sb) != 0) {
    fprintf(stderr,
            "bench_neural_vs_mc: no cached references %s; make them with\n"
            "  nbrdf evaluate --bundle %s --sets layer --count %d --walks %d --cache %s\n",
            path, c->bundle, c->ref_count, c->ref_walks, c->cache);
    exit(1);
  }
  nn_st_reader *r = NULL;
  nbrdf_error err = {0};
  int64_t shape[4] = {c->ref_count, NBRDF_LOBE_N_THETA, NBRDF_LOBE_RES, NBRDF_LOBE_RES}, one = 1;
  const float *x = NULL, *nz = NULL;
  if (nn_st_open(path, &r, &err) || nn_st_expect(r, "images", 4, shape, &x, &err) ||
      nn_st_expect(r, "noise", 1, &one, &nz, &err))
    die(path, &err);
  float *out = malloc((size_t)c->ref_count * PER_BRDF * sizeof *out);
  if (!out) exit(1);
  memcpy(out, x, (size_t)c->ref_count * PER_BRDF * sizeof *out);
  *noise = nz[0];
  nn_st_close(r);
  return out;
}

/* ------------------------------------------------------------ neural */

typedef struct neural_lobe {
  const nbrdf_model *m;
  const float *latent;
  double decode_cpu; /* seconds inside nbrdf_model_decode */
  size_t queries;
} neural_lobe;

static nbrdf_status neural_fn(void *user, size_t n, const nbrdf_query *q, double *f,
                              nbrdf_error *err) {
  neural_lobe *b = user;
  size_t D = (size_t)nbrdf_model_latent_dim(b->m);
  float *lat = malloc(n * D * sizeof *lat), *dirs = malloc(6 * n * sizeof *dirs);
  float *out = malloc(n * sizeof *out);
  nbrdf_status st = lat && dirs && out ? NBRDF_OK : core_fail(err, NBRDF_ERR_MEMORY, "no memory");
  for (size_t k = 0; k < n && !st; k++) {
    memcpy(lat + k * D, b->latent, D * sizeof *lat);
    for (int j = 0; j < 3; j++)
      dirs[3 * k + j] = (float)q[k].wi[j], dirs[3 * (n + k) + j] = (float)q[k].wo[j];
  }
  double c0 = bench_cpu_seconds();
  if (!st) st = nbrdf_model_decode(b->m, n, 1, lat, dirs, dirs + 3 * n, out, err);
  b->decode_cpu += bench_cpu_seconds() - c0;
  b->queries += n;
  for (size_t k = 0; k < n && !st; k++)
    f[k] = out[k];
  free(lat), free(dirs), free(out);
  return st;
}

typedef struct layer_inputs {
  float *a1, *eta, *a2, *r0;
  float *albedo, *sigma_t, *top, *bottom;
} layer_inputs;

/* Latents of BRDFs [i0, i0 + n) as a bake obtains them: two table look-ups, one layering. */
static void layered_latents(const nbrdf_model *m, const layer_inputs *in, size_t i0, size_t n,
                            float *out) {
  nbrdf_error err = {0};
  size_t D = (size_t)nbrdf_model_latent_dim(m);
  if (nbrdf_model_base_latents(m, NBRDF_BASE_DIELECTRIC, n, in->a1 + i0, in->eta + i0,
                               NBRDF_RANGE_CLAMP, in->top + i0 * D, NULL, &err) ||
      nbrdf_model_base_latents(m, NBRDF_BASE_CONDUCTOR, n, in->a2 + i0, in->r0 + i0,
                               NBRDF_RANGE_CLAMP, in->bottom + i0 * D, NULL, &err) ||
      nbrdf_model_layer(m, n, in->top + i0 * D, in->bottom + i0 * D, in->albedo + i0,
                        in->sigma_t + i0, out + i0 * D, &err))
    die("layering", &err);
}

/* CPU seconds per BRDF of layered_latents in batches of `batch`, repeated >= 0.5 s. */
static double layering_cost(const nbrdf_model *m, const layer_inputs *in, size_t n, size_t batch,
                            float *out) {
  size_t done = 0;
  double c0 = bench_cpu_seconds();
  do {
    for (size_t i = 0; i + batch <= n; i += batch)
      layered_latents(m, in, i, batch, out), done += batch;
  } while (bench_cpu_seconds() - c0 < 0.5);
  return (bench_cpu_seconds() - c0) / (double)done;
}

/* ------------------------------------------------------------ matching */

/* The spp at which a curve err(spp) (n points, increasing spp) reaches `target`:
 * log-log interpolation between the bracketing points, else extrapolation from
 * the nearest end as 1/√spp (an unbiased estimator's rate). *extrapolated is set
 * when the target lies outside the measured range. */
static double spp_for(const int *spp, const double *err, int n, double target, int *extrapolated) {
  *extrapolated = 0;
  for (int k = 0; k + 1 < n; k++) {
    double e0 = err[k], e1 = err[k + 1];
    if ((e0 >= target && target >= e1) || (e0 <= target && target <= e1)) {
      if (e0 == e1) return spp[k];
      double t = log(target / e0) / log(e1 / e0);
      return exp(log(spp[k]) + t * (log(spp[k + 1]) - log(spp[k])));
    }
  }
  *extrapolated = 1;
  int k = target > err[0] ? 0 : n - 1;
  double s = spp[k] * pow(err[k] / target, 2.0);
  return s;
}

/* ------------------------------------------------------------ main */

typedef struct mc_point {
  double err, paired, cpu; /* per BRDF: error vs ref. (mean of 2 runs), paired error, CPU s */
} mc_point;

int main(int argc, char **argv) {
  config c;
  if (!parse_args(argc, argv, &c)) {
    usage(stderr);
    return 2;
  }
  openblas_set_num_threads(1); /* process-global: the bench may, the library does not */
  double ref_noise = 0;
  float *refs = load_references(&c, &ref_noise);
  nbrdf_error err = {0};
  nbrdf_model *m = NULL;
  if (nbrdf_model_load(c.bundle, &m, &err)) die("loading the bundle", &err);
  const size_t n = (size_t)c.ref_count, D = (size_t)nbrdf_model_latent_dim(m);
  const double load0 = bench_load_average(), t0 = bench_wall_seconds();
  const double gflops = bench_sgemm_gflops(4096, 128, 128, 0.5, 1);

  train_params *p = malloc(n * sizeof *p);
  layer_inputs in = {
      malloc(4 * n * sizeof(float)),     NULL, NULL, NULL, malloc(2 * n * sizeof(float)), NULL,
      malloc(2 * n * D * sizeof(float)), NULL};
  float *lat = malloc(n * D * sizeof *lat);
  double *ref = malloc(PER_BRDF * sizeof *ref), *x = malloc(PER_BRDF * sizeof *x);
  double *y = malloc(PER_BRDF * sizeof *y), *neural_err = malloc(n * sizeof *neural_err);
  mc_point *mc = calloc((size_t)c.mc_count * MAX_SPP, sizeof *mc);
  if (!p || !in.a1 || !in.albedo || !in.top || !lat || !ref || !x || !y || !neural_err || !mc)
    return 1;
  in.eta = in.a1 + n, in.a2 = in.a1 + 2 * n, in.r0 = in.a1 + 3 * n;
  in.sigma_t = in.albedo + n, in.bottom = in.top + n * D;
  const uint64_t family = train_heldout_seed(TRAIN_HELDOUT_LAYER);
  for (size_t i = 0; i < n; i++) {
    train_params_draw(family, train_heldout_kind(TRAIN_HELDOUT_LAYER), i, &p[i]);
    in.a1[i] = (float)p[i].coat[0].alpha, in.eta[i] = (float)p[i].coat[0].eta;
    in.a2[i] = (float)p[i].base_alpha, in.r0[i] = (float)p[i].base_r0;
    in.albedo[i] = (float)p[i].coat[0].albedo, in.sigma_t[i] = (float)p[i].coat[0].sigma_t;
  }

  /* (a) Neural: layering once per BRDF (one at a time, as nbrdf evaluate does, and batched,
   * as a bake does), then the lobe images by the decoder. */
  const double layer_1 = layering_cost(m, &in, n, 1, lat);
  const double layer_b = layering_cost(m, &in, n, n, lat);
  neural_lobe nl = {m, NULL, 0, 0};
  double neural_cpu0 = bench_cpu_seconds();
  for (size_t i = 0; i < n; i++) {
    nl.latent = lat + i * D;
    if (lobe_images(neural_fn, &nl, NBRDF_LOBE_RES, NBRDF_LOBE_N_THETA, lobe_theta_deg, x, &err))
      die("neural lobes", &err);
    for (size_t k = 0; k < PER_BRDF; k++)
      ref[k] = refs[i * PER_BRDF + k];
    neural_err[i] = lobe_l1_error(PER_BRDF, ref, x);
  }
  const double neural_query = nl.decode_cpu / (double)nl.queries;
  const double neural_query_all = (bench_cpu_seconds() - neural_cpu0) / (double)nl.queries;
  fprintf(stderr, "neural: median lobe error %.2f %% over %zu BRDFs, %.3f us per query\n",
          100 * quantile(neural_err, (int)n, 0.5), n, 1e6 * neural_query);

  /* (b) Monte Carlo per query, two independent runs per spp. */
  const size_t queries = NBRDF_LOBE_N_THETA * lobe_pixels_inside(NBRDF_LOBE_RES);
  for (int i = 0; i < c.mc_count; i++) {
    nbrdf_brdf *b = NULL;
    if (train_params_create(&p[i], &b, &err)) die("ground truth", &err);
    for (size_t k = 0; k < PER_BRDF; k++)
      ref[k] = refs[(size_t)i * PER_BRDF + k];
    for (int s = 0; s < c.n_spp; s++) {
      mc_point *pt = &mc[(size_t)i * MAX_SPP + s];
      double c0 = bench_cpu_seconds();
      for (int run = 0; run < 2; run++) {
        lobe_brdf lb = {b, {core_hash64((uint64_t)i, (uint64_t)(2 * s + run)), c.spp[s], 1}};
        if (lobe_images(lobe_brdf_fn, &lb, NBRDF_LOBE_RES, NBRDF_LOBE_N_THETA, lobe_theta_deg,
                        run ? y : x, &err))
          die("Monte Carlo lobes", &err);
      }
      pt->cpu = (bench_cpu_seconds() - c0) / 2;
      pt->err = 0.5 * (lobe_l1_error(PER_BRDF, ref, x) + lobe_l1_error(PER_BRDF, ref, y));
      double num = 0, den = 0;
      for (size_t k = 0; k < PER_BRDF; k++)
        num += fabs(x[k] - y[k]), den += fabs(ref[k]);
      pt->paired = den > 0 ? num / den / sqrt(2.0) : 0;
    }
    nbrdf_brdf_destroy(b);
    fprintf(stderr, "  Monte Carlo: %d/%d BRDFs, %.0f s\n", i + 1, c.mc_count,
            bench_wall_seconds() - t0);
  }

  /* Medians over the Monte Carlo subset, per spp. */
  double med_err[MAX_SPP], med_paired[MAX_SPP], us_query[MAX_SPP], walks_cpu[MAX_SPP];
  double *v = malloc(n * sizeof *v), *w = malloc(n * sizeof *w);
  if (!v || !w) return 1;
  for (int s = 0; s < c.n_spp; s++) {
    double cpu = 0;
    for (int i = 0; i < c.mc_count; i++) {
      const mc_point *pt = &mc[(size_t)i * MAX_SPP + s];
      v[i] = pt->err, w[i] = pt->paired, cpu += pt->cpu;
    }
    med_err[s] = quantile(v, c.mc_count, 0.5), med_paired[s] = quantile(w, c.mc_count, 0.5);
    us_query[s] = 1e6 * cpu / ((double)c.mc_count * (double)queries);
    walks_cpu[s] = (double)c.spp[s] * (double)c.mc_count * (double)queries / cpu;
  }
  const double neural_med_all = quantile(neural_err, (int)n, 0.5);
  const double neural_p90_all = quantile(neural_err, (int)n, 0.9);
  const double neural_med_sub = quantile(neural_err, c.mc_count, 0.5);

  /* Walks per query for equal error, on the median curves and per BRDF, and the Monte
   * Carlo cost at a fractional spp from a least-squares line through the measured
   * (spp, cost per query) points (a fixed cost per query plus one per walk). */
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int s = 0; s < c.n_spp; s++)
    sx += c.spp[s], sy += us_query[s], sxx += (double)c.spp[s] * c.spp[s],
        sxy += c.spp[s] * us_query[s];
  const double us_walk = (c.n_spp * sxy - sx * sy) / (c.n_spp * sxx - sx * sx);
  const double us_fixed = fmax(0.0, (sy - us_walk * sx) / c.n_spp);
#define MC_US(spp) (us_fixed + us_walk * (spp))
  int ex_med, ex_t, n_ex = 0;
  const double spp_med = spp_for(c.spp, med_err, c.n_spp, neural_med_sub, &ex_med);
  const double spp_t = spp_for(c.spp, med_paired, c.n_spp, c.target, &ex_t);
  double *match = malloc(n * sizeof *match);
  if (!match) return 1;
  for (int i = 0; i < c.mc_count; i++) {
    double e[MAX_SPP];
    int ex;
    for (int s = 0; s < c.n_spp; s++)
      e[s] = mc[(size_t)i * MAX_SPP + s].err;
    match[i] = spp_for(c.spp, e, c.n_spp, neural_err[i], &ex);
    w[i] = MC_US(match[i]) / (1e6 * neural_query);
    n_ex += ex;
  }
  const double wall = bench_wall_seconds() - t0;

  FILE *out = fopen(c.out, "w");
  if (!out) {
    fprintf(stderr, "bench_neural_vs_mc: cannot write %s\n", c.out);
    return 1;
  }
  FILE *streams[2] = {stdout, out};
  for (int o = 0; o < 2; o++) {
    FILE *f = streams[o];
    fprintf(f,
            "Bundle `%s` (%s, checksum %s); references %s/ref-layer-n%d-w%d.safetensors (%d "
            "whole-lobe walks per image; their own seed-to-seed lobe error %.2f %%, median of "
            "10 BRDFs). 1 thread, CPU time; sgemm 4096x128x128: %.1f GFLOP/s. Wall %.0f s; load "
            "average %.2f at the start, %.2f at the end (shared 2-core machine).\n\n",
            c.bundle, nbrdf_model_name(m), nbrdf_model_checksum(m), c.cache, c.ref_count,
            c.ref_walks, c.ref_walks, 100 * ref_noise, gflops, wall, load0, bench_load_average());
    fprintf(f, "| estimator | BRDFs | median lobe error vs ref. | 90th pct | paired error (no "
               "ref. noise) | CPU us per query | walks per CPU-s |\n"
               "|---|---:|---:|---:|---:|---:|---:|\n");
    fprintf(f, "| neural (decoder; layering below) | %zu | %.2f %% | %.2f %% | - | %.3f | - |\n", n,
            100 * neural_med_all, 100 * neural_p90_all, 1e6 * neural_query);
    fprintf(f, "| neural, first %d only | %d | %.2f %% | %.2f %% | - | %.3f | - |\n", c.mc_count,
            c.mc_count, 100 * neural_med_sub, 100 * quantile(neural_err, c.mc_count, 0.9),
            1e6 * neural_query);
    for (int s = 0; s < c.n_spp; s++) {
      for (int i = 0; i < c.mc_count; i++)
        v[i] = mc[(size_t)i * MAX_SPP + s].err;
      fprintf(f,
              "| Monte Carlo, %d walks/query | %d | %.2f %% | %.2f %% | %.2f %% | %.2f | %.3g |\n",
              c.spp[s], c.mc_count, 100 * med_err[s], 100 * quantile(v, c.mc_count, 0.9),
              100 * med_paired[s], us_query[s], walks_cpu[s]);
    }
    fprintf(f,
            "\nNeural cost besides the decoder: layering (2 table look-ups + layering network) "
            "%.1f us per BRDF one at a time, %.1f us per BRDF in a batch of %zu; the decoder "
            "through nbrdf_model_decode %.3f us per query (%.3f us with building the inputs), "
            "%lld MACs per query = %.1f GFLOP/s, %.0f %% of sgemm.\n\n",
            1e6 * layer_1, 1e6 * layer_b, n, 1e6 * neural_query, 1e6 * neural_query_all,
            (long long)nbrdf_model_decoder_macs(m),
            2e-9 * (double)nbrdf_model_decoder_macs(m) / neural_query,
            100 * 2e-9 * (double)nbrdf_model_decoder_macs(m) / neural_query / gflops);
    fprintf(f, "| equal error | Monte Carlo walks per query | MC CPU us per query | neural CPU us "
               "per query | MC / neural |\n|---|---:|---:|---:|---:|\n");
    fprintf(f,
            "| median curves: neural %.2f %% (first %d BRDFs) | %.1f%s | %.2f | %.3f | %.0fx |\n",
            100 * neural_med_sub, c.mc_count, spp_med, ex_med ? " (extrapolated)" : "",
            MC_US(spp_med), 1e6 * neural_query, MC_US(spp_med) / (1e6 * neural_query));
    fprintf(f,
            "| per BRDF (median of %d; %d extrapolated) | %.1f | %.2f | %.3f | %.0fx (10th pct "
            "%.0fx, 90th %.0fx) |\n",
            c.mc_count, n_ex, quantile(match, c.mc_count, 0.5),
            MC_US(quantile(match, c.mc_count, 0.5)), 1e6 * neural_query,
            quantile(w, c.mc_count, 0.5), quantile(w, c.mc_count, 0.1),
            quantile(w, c.mc_count, 0.9));
    fprintf(f,
            "| paired error %.1f %% (issue 5's layer target; no neural figure at it) | %.0f%s | "
            "%.1f | %.3f | %.0fx |\n\n",
            100 * c.target, spp_t, ex_t ? " (extrapolated)" : "", MC_US(spp_t), 1e6 * neural_query,
            MC_US(spp_t) / (1e6 * neural_query));
    fprintf(f,
            "Monte Carlo cost model (least squares over the rows above): %.3f us per query + "
            "%.3f us per walk.\n\n",
            us_fixed, us_walk);
  }
  fclose(out);

  /* Plot: median lobe error against CPU cost per query. */
  double nx = 1e6 * neural_query, ny = 100 * neural_med_sub, e_pct[MAX_SPP], p_pct[MAX_SPP];
  for (int s = 0; s < c.n_spp; s++)
    e_pct[s] = 100 * med_err[s], p_pct[s] = 100 * med_paired[s];
  double floor_x[2] = {nx, us_query[c.n_spp - 1]}, floor_y[2] = {100 * ref_noise, 100 * ref_noise};
  bench_plot_series ser[4] = {
      {"monte carlo vs reference", c.n_spp, us_query, e_pct, 0, 0},
      {"monte carlo paired (no ref. noise)", c.n_spp, us_query, p_pct, 1, 1},
      {"neural (decoder per query)", 1, &nx, &ny, 0, 0},
      {"reference seed-to-seed", 2, floor_x, floor_y, 1, 0}};
  bench_plot_options po = {"Layer set: median lobe error vs CPU cost per query",
                           "CPU microseconds per query (1 thread)",
                           "median lobe error (%)",
                           1,
                           1,
                           0,
                           0};
  if (bench_plot_write_png(c.plot, &po, 4, ser, &err)) die(c.plot, &err);
  fprintf(stderr, "wrote %s and %s\n", c.out, c.plot);

  free(match), free(v), free(w), free(mc), free(neural_err), free(x), free(y), free(ref), free(lat);
  free(in.a1), free(in.albedo), free(in.top), free(p), free(refs);
  nbrdf_model_destroy(m);
  return 0;
}
