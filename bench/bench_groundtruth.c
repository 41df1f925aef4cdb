/* Ground-truth benchmark (issue 2, METRICS.md): Monte Carlo random walks per
 * second per core, and the lobe error of the layered estimator against a
 * high-sample-count reference as a function of walks (samples) per query, for
 * three representative layered BRDFs. Prints a markdown table, writes it to a
 * file and plots lobe error against spp. docs/BENCH_GROUND_TRUTH.md has the figures
 * and the command that produced them. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "brdf/brdf_handle.h"
#include "brdf/layered_lobe.h"
#include "lobe/lobe.h"
#include "lobe/lobe_png.h"
#include "support/plot.h"
#include "nbrdf/brdf.h"

#include "bench_args.h"
#include "bench_clock.h"

enum { MAX_SPP = 16, N_BRDF = 3, N_THETA = NBRDF_LOBE_N_THETA, ALBEDO_SAMPLES = 1 << 18 };

typedef struct preset {
  const char *name, *label;
  double alpha1, eta, alpha2, r0, albedo, sigma_t;
} preset;

static const preset PRESETS[N_BRDF] = {
    {"coat", "smooth coat over rough metal", 0.02, 1.5, 0.5, 0.9, 0.5, 0.0},
    {"rough", "rough over smooth", 0.6, 1.5, 0.02, 0.9, 0.8, 1.0},
    {"thick", "thick scattering medium", 0.1, 1.5, 0.3, 0.5, 0.95, 5.0},
};

typedef struct config {
  int spp[MAX_SPP], n_spp, ref_spp, ref_walks, res, threads, speed_spp;
  const char *only, *out, *plot, *lobes;
} config;

static void usage(FILE *f) {
  fprintf(f,
          "usage: bench_groundtruth [--spp 16,64,256,1024] [--ref-walks 16000 | --ref-spp N]\n"
          "                         [--res 64] [--threads T] [--brdf coat|rough|thick]\n"
          "                         [--out FILE.md] [--plot FILE.png] [--lobes DIR]\n"
          "Lobe error (METRICS.md: 64x64 images at theta_i = 0, 30, 60, 80 deg) of the layered\n"
          "Monte Carlo estimator (per-pixel evaluation, as nbrdf eval does it) at each spp\n"
          "against a reference: the mean of two runs of the whole-lobe estimator with\n"
          "--ref-walks walks per image (src/brdf/layered_lobe.h; every walk feeds every pixel),\n"
          "or with --ref-walks 0, of per-pixel evaluation with --ref-spp walks per pixel. The\n"
          "two runs' seed-to-seed error is reported beside each figure, and the paired error\n"
          "of two runs at each spp (no reference noise in it). Walks per second and per\n"
          "CPU-second on 1 thread and on T threads (0 = all cores). --lobes DIR writes\n"
          "reference | estimate | difference PNGs at the lowest spp.\n");
}

static int parse_args(int argc, char **argv, config *c) {
  *c = (config){.spp = {16, 64, 256, 1024},
                .n_spp = 4,
                .ref_spp = 1024,
                .ref_walks = 16000,
                .res = NBRDF_LOBE_RES,
                .speed_spp = 64,
                .out = "groundtruth.md",
                .plot = "groundtruth.png"};
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *v = bench_option_value(argc, argv, &i, "bench_groundtruth", usage);
    if (!v) return 0;
    if (!strcmp(a, "--spp")) {
      c->n_spp = bench_parse_counts(v, c->spp, MAX_SPP, 1, 1L << 30, 0); /* 0: rejected below */
    } else if (!strcmp(a, "--ref-spp")) {
      c->ref_spp = atoi(v);
    } else if (!strcmp(a, "--ref-walks")) {
      c->ref_walks = atoi(v);
    } else if (!strcmp(a, "--res")) {
      c->res = atoi(v);
    } else if (!strcmp(a, "--threads")) {
      c->threads = atoi(v);
    } else if (!strcmp(a, "--brdf")) {
      c->only = v;
    } else if (!strcmp(a, "--out")) {
      c->out = v;
    } else if (!strcmp(a, "--plot")) {
      c->plot = v;
    } else if (!strcmp(a, "--lobes")) {
      c->lobes = v;
    } else {
      fprintf(stderr, "bench_groundtruth: unknown option %s\n", a);
      return 0;
    }
  }
  for (int k = 0; k < c->n_spp; k++)
    if (c->spp[k] < 1) c->n_spp = 0;
  int known = !c->only;
  for (int i = 0; i < N_BRDF; i++)
    known |= c->only && !strcmp(c->only, PRESETS[i].name);
  if (!known) {
    fprintf(stderr, "bench_groundtruth: --brdf must be coat, rough or thick\n");
    return 0;
  }
  if (c->n_spp == 0 || c->ref_spp < 1 || c->ref_walks < 0 || c->res < 8 || c->res > 1024 ||
      c->threads < 0) {
    fprintf(stderr, "bench_groundtruth: bad --spp, --ref-spp, --ref-walks, --res or --threads\n");
    return 0;
  }
  return 1;
}

static void cpu_model(char *buf, size_t cap) {
  snprintf(buf, cap, "unknown CPU");
  FILE *f = fopen("/proc/cpuinfo", "r");
  char line[512];
  while (f && fgets(line, sizeof line, f)) {
    char *colon = strchr(line, ':');
    if (strncmp(line, "model name", 10) || !colon) continue;
    snprintf(buf, cap, "%s", colon + 2);
    buf[strcspn(buf, "\n")] = '\0';
    break;
  }
  if (f) fclose(f);
}

typedef struct timing {
  double wall, cpu; /* seconds; cpu: of all threads of the process */
} timing;

static timing add(timing a, timing b) { return (timing){a.wall + b.wall, a.cpu + b.cpu}; }

/* Lobe images of `b` by per-pixel evaluation, `spp` walks per pixel. */
static timing lobe_set(const nbrdf_brdf *b, int res, int spp, uint64_t seed, int threads,
                       double *images) {
  lobe_brdf lb = {b, {seed, spp, threads}};
  nbrdf_error err = {0};
  const double t0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
  if (lobe_images(lobe_brdf_fn, &lb, res, N_THETA, lobe_theta_deg, images, &err) != NBRDF_OK) {
    fprintf(stderr, "bench_groundtruth: %s\n", err.message);
    exit(1);
  }
  return (timing){bench_wall_seconds() - t0, bench_cpu_seconds() - c0};
}

/* The same images by the whole-lobe estimator (src/brdf/layered_lobe.h): each of
 * `walks` walks from ωi contributes to every pixel of its image. */
static timing lobe_set_whole(const nbrdf_brdf *b, int res, int walks, uint64_t seed, int threads,
                             double *images) {
  const brdf_bsdf_layered *l = &brdf_handle_bsdf(b)->layered;
  const double t0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
  for (int t = 0; t < N_THETA; t++)
    if (!brdf_layered_lobe_image(l, lobe_theta_deg[t] * (M_PI / 180.0), res, walks,
                                 seed * N_THETA + (uint64_t)t, threads,
                                 images + (size_t)t * (size_t)res * (size_t)res, NULL)) {
      fprintf(stderr, "bench_groundtruth: out of memory in the whole-lobe estimator\n");
      exit(1);
    }
  return (timing){bench_wall_seconds() - t0, bench_cpu_seconds() - c0};
}

/* Σ|x − y| / Σ|ref| / √2. For an unbiased estimator with independent errors,
 * E|x − y| = √2 E|x − truth| (exact for Gaussian errors), so this is the lobe
 * error of one run without the reference's own noise in it. */
static double paired_error(size_t n, const double *ref, const double *x, const double *y) {
  double num = 0, den = 0;
  for (size_t k = 0; k < n; k++)
    num += fabs(x[k] - y[k]), den += fabs(ref[k]);
  return den > 0 ? num / den / sqrt(2.0) : 0.0;
}

typedef struct result {
  double err[MAX_SPP];        /* lobe error against the reference */
  double paired[MAX_SPP];     /* see paired_error() */
  double albedo_err[MAX_SPP]; /* mean |albedo − reference albedo| over the four images */
  double rate[MAX_SPP];       /* walks per second, all threads */
  double cpu_rate[MAX_SPP];   /* walks per CPU-second (robust to other jobs on the machine) */
  double ref_noise, ref_wall, ref_cpu, rate_1, cpu_rate_1, ref_albedo[N_THETA];
  double rho[N_THETA], rho_se[N_THETA]; /* nbrdf_brdf_albedo(), by sampling */
} result;

static void run_preset(const preset *p, const config *c, result *r) {
  nbrdf_brdf *bottom = NULL, *b = NULL;
  nbrdf_error err = {0};
  if (nbrdf_brdf_create_conductor(p->alpha2, p->r0, &bottom, &err) != NBRDF_OK ||
      nbrdf_brdf_create_layered(p->alpha1, p->eta, p->albedo, p->sigma_t, bottom, &b, &err) !=
          NBRDF_OK) {
    fprintf(stderr, "bench_groundtruth: %s: %s\n", p->name, err.message);
    exit(1);
  }
  nbrdf_brdf_destroy(bottom);
  const size_t per_image = (size_t)c->res * (size_t)c->res, n_pix = N_THETA * per_image;
  const double walks_per_spp = (double)N_THETA * (double)lobe_pixels_inside(c->res);
  double *ref = malloc(n_pix * sizeof *ref), *x = malloc(n_pix * sizeof *x);
  double *y = malloc(n_pix * sizeof *y);
  if (!ref || !x || !y) exit(1);

  timing dt = lobe_set(b, c->res, c->speed_spp, 99, 1, x);
  r->rate_1 = walks_per_spp * c->speed_spp / dt.wall;
  r->cpu_rate_1 = walks_per_spp * c->speed_spp / dt.cpu;
  fprintf(stderr, "  1 thread: %.3g walks/s, %.3g walks/CPU-s\n", r->rate_1, r->cpu_rate_1);

  /* The reference: the mean of two independent runs; their difference is its noise. */
  if (c->ref_walks > 0) {
    dt = lobe_set_whole(b, c->res, c->ref_walks, 1001, c->threads, ref);
    dt = add(dt, lobe_set_whole(b, c->res, c->ref_walks, 1002, c->threads, y));
  } else {
    dt = lobe_set(b, c->res, c->ref_spp, 1001, c->threads, ref);
    dt = add(dt, lobe_set(b, c->res, c->ref_spp, 1002, c->threads, y));
  }
  r->ref_wall = dt.wall;
  r->ref_cpu = dt.cpu;
  r->ref_noise = lobe_l1_error(n_pix, ref, y);
  for (size_t k = 0; k < n_pix; k++)
    ref[k] = 0.5 * (ref[k] + y[k]);
  for (int t = 0; t < N_THETA; t++)
    r->ref_albedo[t] = lobe_albedo(c->res, ref + (size_t)t * per_image);
  fprintf(stderr, "  reference: seed-to-seed %.2f %% (%.0f s, %.0f CPU-s)\n", 100 * r->ref_noise,
          dt.wall, dt.cpu);
  /* The same albedo from the sampler's mean weight: a check that evaluation and
   * sampling agree, and a measure of the lobe images' pixelisation. */
  for (int t = 0; t < N_THETA; t++)
    if (nbrdf_brdf_albedo(b, lobe_theta_deg[t] * (M_PI / 180.0), ALBEDO_SAMPLES, 5, &r->rho[t],
                          &r->rho_se[t], &err) != NBRDF_OK) {
      fprintf(stderr, "bench_groundtruth: %s: %s\n", p->name, err.message);
      exit(1);
    }

  for (int k = 0; k < c->n_spp; k++) {
    dt = lobe_set(b, c->res, c->spp[k], 7 + 2 * (uint64_t)k, c->threads, x);
    dt = add(dt, lobe_set(b, c->res, c->spp[k], 8 + 2 * (uint64_t)k, c->threads, y));
    r->rate[k] = 2 * walks_per_spp * c->spp[k] / dt.wall;
    r->cpu_rate[k] = 2 * walks_per_spp * c->spp[k] / dt.cpu;
    r->err[k] = lobe_l1_error(n_pix, ref, x);
    r->paired[k] = paired_error(n_pix, ref, x, y);
    r->albedo_err[k] = lobe_albedo_error(c->res, N_THETA, ref, x, NULL);
    fprintf(stderr, "  spp %d: lobe error %.2f %%, paired %.2f %% (%.1f s)\n", c->spp[k],
            100 * r->err[k], 100 * r->paired[k], dt.wall);
    if (c->lobes && k == 0) {
      char path[1024];
      snprintf(path, sizeof path, "%s/groundtruth_%s_spp%d.png", c->lobes, p->name, c->spp[k]);
      if (lobe_write_png(path, c->res, N_THETA, ref, x, 3, &err) != NBRDF_OK)
        fprintf(stderr, "bench_groundtruth: %s\n", err.message);
    }
  }
  free(ref), free(x), free(y);
  nbrdf_brdf_destroy(b);
}

static void print_table(FILE *f, const char *head, const config *c, int threads_used,
                        const int *ran, const result *res, double seconds) {
  fprintf(f, "%s\n", head);
  fprintf(f,
          "| BRDF (alpha1, eta, alpha2, R0, A, sigma_T) | spp | lobe error vs ref. | ref. "
          "seed-to-seed | > 3x ref.? | paired error | albedo error | walks/s (%d thr) | walks "
          "per CPU-s |\n",
          threads_used);
  fprintf(f, "|---|---:|---:|---:|:---:|---:|---:|---:|---:|\n");
  for (int i = 0; i < N_BRDF; i++) {
    if (!ran[i]) continue;
    const preset *p = &PRESETS[i];
    for (int k = 0; k < c->n_spp; k++) {
      char name[160] = "";
      if (k == 0)
        snprintf(name, sizeof name, "%s (%g, %g, %g, %g, %g, %g)", p->label, p->alpha1, p->eta,
                 p->alpha2, p->r0, p->albedo, p->sigma_t);
      fprintf(f, "| %s | %d | %.2f %% | %.2f %% | %s | %.2f %% | %.4f | %.3g | %.3g |\n", name,
              c->spp[k], 100 * res[i].err[k], 100 * res[i].ref_noise,
              res[i].err[k] > 3 * res[i].ref_noise ? "yes" : "no", 100 * res[i].paired[k],
              res[i].albedo_err[k], res[i].rate[k], res[i].cpu_rate[k]);
    }
  }
  fprintf(f,
          "\nOne core (1 thread, %d walks per query): walks per second (wall clock) and per "
          "CPU-second; walks per query for a 3 %% and a 1 %% lobe error, extrapolated as "
          "1/sqrt(spp) from the paired error at the largest spp; the reference's cost:\n",
          c->speed_spp);
  for (int i = 0; i < N_BRDF; i++) {
    if (!ran[i]) continue;
    const double e = res[i].paired[c->n_spp - 1], k2 = e * e * c->spp[c->n_spp - 1];
    fprintf(f,
            "- %s: %.3g walks/s, %.3g walks/CPU-s; %.0f spp for 3 %%, %.0f spp for 1 %%; "
            "reference %.0f s (%.0f CPU-s)\n",
            PRESETS[i].label, res[i].rate_1, res[i].cpu_rate_1, k2 / (0.03 * 0.03),
            k2 / (0.01 * 0.01), res[i].ref_wall, res[i].ref_cpu);
  }
  fprintf(f,
          "\nDirectional albedo at theta_i = 0, 30, 60, 80 deg: from the reference's lobe "
          "images (midpoint rule on the pixels) | from the sampler's mean weight "
          "(nbrdf_brdf_albedo, %d walks, +- 1 standard error):\n",
          ALBEDO_SAMPLES);
  for (int i = 0; i < N_BRDF; i++) {
    if (!ran[i]) continue;
    fprintf(f, "- %s: ", PRESETS[i].label);
    for (int t = 0; t < N_THETA; t++)
      fprintf(f, "%s%.4f | %.4f +- %.4f", t ? "; " : "", res[i].ref_albedo[t], res[i].rho[t],
              res[i].rho_se[t]);
    fprintf(f, "\n");
  }
  fprintf(f, "\nTotal time %.0f s.\n", seconds);
}

static void plot(const config *c, const int *ran, const result *res) {
  double xs[MAX_SPP], ys[N_BRDF][MAX_SPP], floor_y[N_BRDF][MAX_SPP];
  bench_plot_series s[2 * N_BRDF];
  int n = 0;
  for (int k = 0; k < c->n_spp; k++)
    xs[k] = c->spp[k];
  for (int i = 0; i < N_BRDF; i++) {
    if (!ran[i]) continue;
    for (int k = 0; k < c->n_spp; k++) {
      ys[i][k] = 100 * res[i].err[k];
      floor_y[i][k] = 100 * res[i].ref_noise;
    }
    s[n++] = (bench_plot_series){PRESETS[i].label, c->n_spp, xs, ys[i], 0, i + 1};
    s[n++] = (bench_plot_series){NULL, c->n_spp, xs, floor_y[i], 1, i + 1};
  }
  bench_plot_options o = NBRDF_PLOT_OPTIONS_DEFAULT;
  o.title = "Layered ground truth: lobe error vs walks per query";
  o.x_label = "walks per query (spp)";
  o.y_label = "lobe error vs reference (%), dashed: reference seed-to-seed";
  o.log_x = o.log_y = 1;
  o.width = 900;
  nbrdf_error err = {0};
  if (bench_plot_write_png(c->plot, &o, n, s, &err) != NBRDF_OK)
    fprintf(stderr, "bench_groundtruth: %s\n", err.message);
}

int main(int argc, char **argv) {
  config c;
  if (!parse_args(argc, argv, &c)) {
    usage(stderr);
    return 2;
  }
  const int threads_used = c.threads > 0 ? c.threads : omp_get_max_threads();
  char cpu[256], ref[160], head[1024];
  cpu_model(cpu, sizeof cpu);
  if (c.ref_walks > 0)
    snprintf(ref, sizeof ref, "2 whole-lobe runs x %d walks per image", c.ref_walks);
  else
    snprintf(ref, sizeof ref, "2 per-pixel runs x %d walks per pixel", c.ref_spp);
  snprintf(head, sizeof head,
           "Machine: %s, %d logical cores (omp_get_max_threads), %d threads used, load average "
           "%.2f at start.\nLobe images: %dx%d at theta_i = 0, 30, 60, 80 deg (%zu queries per "
           "set); reference = mean of %s (seeds 1001, 1002).\n",
           cpu, omp_get_max_threads(), threads_used, bench_load_average(), c.res, c.res,
           (size_t)N_THETA * lobe_pixels_inside(c.res), ref);
  fprintf(stderr, "%s", head);

  result res[N_BRDF];
  int ran[N_BRDF] = {0};
  const double t_start = bench_wall_seconds();
  for (int i = 0; i < N_BRDF; i++) {
    if (c.only && strcmp(c.only, PRESETS[i].name)) continue;
    fprintf(stderr, "%s (%s):\n", PRESETS[i].label, PRESETS[i].name);
    run_preset(&PRESETS[i], &c, &res[i]);
    ran[i] = 1;
  }
  const double seconds = bench_wall_seconds() - t_start;
  print_table(stdout, head, &c, threads_used, ran, res, seconds);
  FILE *out = fopen(c.out, "w");
  if (out) {
    print_table(out, head, &c, threads_used, ran, res, seconds);
    fclose(out);
  } else {
    fprintf(stderr, "bench_groundtruth: cannot write %s\n", c.out);
  }
  plot(&c, ran, res);
  fprintf(stderr, "wrote %s and %s\n", c.out, c.plot);
  return 0;
}
