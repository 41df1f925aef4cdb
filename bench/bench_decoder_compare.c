/* The representation's speed/accuracy trade: for each decoder given, its
 * cost (MACs per query, decoded queries per CPU-second on one thread, batches
 * of 4096 like a bake's verify or a renderer's tile) and its accuracy on the
 * held-out `rep` set (METRICS.md lobe error of projected latents, the same
 * evaluation as `nbrdf evaluate --sets rep`, references from the cache).
 * Prints a Markdown table and plots median lobe error against cost.
 *
 *   bench_decoder_compare [--cache data/evalcache] [--out FILE.md] [--plot FILE.png]
 *                         [--walks 2000] NAME=DECODER.safetensors ...
 *
 * How the decoders were trained (equal compute, docs/TRAINING.md) is the
 * caller's business; this program only measures them. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "eval/evaluate.h"
#include "support/plot.h"
#include "model/decoder.h"

#include "bench_args.h"
#include "bench_clock.h"

#define MAX_DECODERS 16
#define BATCH 4096

static void usage(FILE *f) {
  fprintf(f, "usage: bench_decoder_compare [--cache data/evalcache] [--out FILE.md] "
             "[--plot FILE.png] [--walks 2000] NAME=DECODER.safetensors ...\n");
}

static void die(const char *what, const nbrdf_error *err) {
  fprintf(stderr, "bench_decoder_compare: %s: %s\n", what, err->message);
  exit(1);
}

/* Decoded queries per CPU-second: random latents and directions, one thread. */
static double queries_per_cpu_second(model_decoder *dec) {
  nbrdf_error err;
  model_runner run = {0};
  if (model_runner_create(dec->nn, BATCH, NBRDF_NN_INFER, &run, &err)) die("runner", &err);
  size_t D = (size_t)dec->cfg.latent_dim;
  float *lat = malloc(BATCH * D * sizeof *lat), *wi = malloc(3 * BATCH * sizeof *wi);
  float *wo = malloc(3 * BATCH * sizeof *wo), *f = malloc(BATCH * sizeof *f);
  core_rng rng;
  core_rng_init(&rng, 7, 0);
  for (size_t k = 0; k < BATCH * D; k++)
    lat[k] = (float)(0.3 * core_rng_normal(&rng));
  for (size_t k = 0; k < BATCH; k++) {
    wi[3 * k] = 0.3f, wi[3 * k + 1] = 0.1f, wi[3 * k + 2] = 0.95f;
    wo[3 * k] = -0.2f, wo[3 * k + 1] = 0.4f, wo[3 * k + 2] = 0.89f;
  }
  long calls = 0;
  double t0 = bench_cpu_seconds();
  do {
    if (model_decoder_eval(dec, &run, BATCH, 1, lat, wi, wo, f, &err)) die("decode", &err);
    calls++;
  } while (bench_cpu_seconds() - t0 < 1.0);
  double rate = (double)calls * BATCH / (bench_cpu_seconds() - t0);
  model_runner_destroy(&run);
  free(lat), free(wi), free(wo), free(f);
  return rate;
}

int main(int argc, char **argv) {
  const char *cache = "data/evalcache", *out = "decoder_compare.md", *plot = NULL;
  const char *names[MAX_DECODERS], *paths[MAX_DECODERS];
  int n = 0, walks = 2000;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    if (a[0] == '-' && a[1] == '-' && strcmp(a, "--help")) {
      const char *v = bench_option_value(argc, argv, &i, "bench_decoder_compare", usage);
      if (!v) return 2;
      if (!strcmp(a, "--cache"))
        cache = v;
      else if (!strcmp(a, "--out"))
        out = v;
      else if (!strcmp(a, "--plot"))
        plot = v;
      else if (!strcmp(a, "--walks"))
        walks = atoi(v);
      else {
        usage(stderr);
        return 2;
      }
    } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      usage(stdout);
      return 0;
    } else {
      char *eq = strchr(argv[i], '=');
      if (!eq || n == MAX_DECODERS) {
        usage(stderr);
        return 2;
      }
      *eq = '\0';
      names[n] = argv[i], paths[n++] = eq + 1;
    }
  }
  if (n == 0 || walks < 1) {
    usage(stderr);
    return 2;
  }
  FILE *md = fopen(out, "w");
  if (!md) {
    perror(out);
    return 1;
  }
  double macs[MAX_DECODERS], us[MAX_DECODERS], med[MAX_DECODERS];
  double load0 = bench_load_average(), w0 = bench_wall_seconds();
  fprintf(md, "| decoder | encoding | output | width | MACs per query | queries per CPU-s | "
              "rep median | rep 90th pct | rep worst | median albedo error |\n");
  fprintf(md, "|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int k = 0; k < n; k++) {
    nbrdf_error err;
    model_decoder *dec = NULL;
    if (model_decoder_load(paths[k], &dec, &err)) die(paths[k], &err);
    macs[k] = (double)nn_spec_macs(&dec->cfg.spec);
    double qps = queries_per_cpu_second(dec);
    us[k] = 1e6 / qps;
    eval_settings s = EVAL_SETTINGS_DEFAULT;
    s.walks = walks, s.cache_dir = cache;
    eval_result r;
    if (eval_run(NULL, dec, EVAL_REP, &s, &r, &err)) die(paths[k], &err);
    med[k] = 100 * r.median;
    fprintf(md, "| %s | %s | %s | %d | %.0f | %.3g | %.2f %% | %.1f %% | %.1f %% | %.4f |\n",
            names[k], model_encoding_kind_name(dec->cfg.encoding.kind),
            model_output_name(dec->cfg.output), nn_spec_width(&dec->cfg.spec, 1), macs[k], qps,
            med[k], 100 * r.p90, 100 * r.worst, r.median_albedo_error);
    fflush(md);
    eval_result_free(&r);
    model_decoder_destroy(dec);
  }
  fprintf(md, "\nReferences: %s (rep, 100 BRDFs, %d walks); wall %.0f s; load average %.2f at "
              "the start, %.2f at the end (shared 2-core machine); one OpenBLAS thread if "
              "OPENBLAS_NUM_THREADS=1.\n",
          cache, walks, bench_wall_seconds() - w0, load0, bench_load_average());
  fclose(md);
  if (plot) {
    bench_plot_series series[MAX_DECODERS];
    for (int k = 0; k < n; k++)
      series[k] = (bench_plot_series){names[k], 1, &us[k], &med[k], 0, 0};
    bench_plot_options o = NBRDF_PLOT_OPTIONS_DEFAULT;
    o.title = "decoders: rep median lobe error vs cost";
    o.x_label = "microseconds per query (1 thread)";
    o.y_label = "rep median lobe error (%)";
    o.log_x = 1;
    nbrdf_error err;
    if (bench_plot_write_png(plot, &o, n, series, &err)) die(plot, &err);
  }
  printf("bench_decoder_compare: wrote %s%s%s\n", out, plot ? " and " : "", plot ? plot : "");
  return 0;
}
