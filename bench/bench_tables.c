/* How fine the base-latent tables must be: for each grid given, the lobe error
 * of the held-out `single` BRDFs (METRICS.md) looked up from freshly fitted
 * tables, beside the same BRDFs projected directly (the floor a table cannot
 * beat), and the error the look-up adds (table minus projected, per BRDF).
 * Split by kind, since the dielectric table (α1, η) and the conductor table
 * (α2, R0) are separate grids.
 *
 *   bench_tables --decoder FILE [--grids 16x8x9,24x12x13@2] [--count 100]
 *                [--steps 800] [--csv FILE] [--plot FILE.png]
 *
 * A grid AxExR[@P] has A α nodes shared by both tables, E η nodes and R R0
 * nodes; @P places the η nodes as 1.05 + 0.95·u^P and the R0 nodes as u^P
 * (P > 1: denser at the dim end, where the BRDF changes fastest relative to
 * itself; default 1, uniform). The plot: 90th percentile and median against
 * nodes, one line per warp, the projected BRDFs' as dashed floors. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "eval/evaluate.h"
#include "lobe/lobe.h"
#include "support/plot.h"
#include "model/decoder.h"
#include "train/table_fit.h"

#include "bench_args.h"
#include "bench_clock.h"
#include "bench_sort.h"

#define MAX_GRIDS 8

static void usage(FILE *f) {
  fprintf(f, "usage: bench_tables --decoder FILE [--grids 16x8x9,...] [--count 100] "
             "[--steps 800] [--csv FILE] [--plot FILE.png]\n");
}

static void die(const char *what, const nbrdf_error *err) {
  fprintf(stderr, "bench_tables: %s: %s\n", what, err->message);
  exit(1);
}

/* Median, 90th percentile and worst of the values v[k] whose case matches `kind`
 * (-1: all), as percentages. */
static void stats(const double *v, const eval_case *c, int n, int kind, double out[3]) {
  double *s = malloc((size_t)n * sizeof *s);
  int m = 0;
  for (int k = 0; k < n; k++)
    if (kind < 0 || (int)c[k].params.kind == kind) s[m++] = v[k];
  out[0] = out[1] = out[2] = NAN;
  if (m > 0) {
    qsort(s, (size_t)m, sizeof *s, bench_cmp_double);
    int k90 = (int)ceil(0.9 * m) - 1;
    out[0] = 100 * s[m / 2], out[1] = 100 * s[k90 < 0 ? 0 : k90], out[2] = 100 * s[m - 1];
  }
  free(s);
}

static int parse_grid(const char *s, train_table_settings *t) {
  char tail;
  double warp = 1.0;
  int k = sscanf(s, "%dx%dx%d@%lf%c", &t->alpha_nodes, &t->eta_nodes, &t->r0_nodes, &warp, &tail);
  if (k != 3 && k != 4) return 0;
  if (k == 3 && strchr(s, '@')) return 0;
  t->eta_warp = t->r0_warp = warp;
  return t->alpha_nodes >= 2 && t->eta_nodes >= 2 && t->r0_nodes >= 2 && warp >= 0.25 && warp <= 4;
}

/* Table p90 and median against node count, one pair of lines per warp. */
static void write_plot(const char *path, int n_grids, const train_table_settings *g,
                       const double (*fig)[2], const double proj[2]) {
  double warps[MAX_GRIDS], x[MAX_GRIDS][MAX_GRIDS], y[2][MAX_GRIDS][MAX_GRIDS];
  int n_warps = 0, count[MAX_GRIDS] = {0};
  for (int k = 0; k < n_grids; k++) {
    int w = 0;
    while (w < n_warps && warps[w] != g[k].eta_warp)
      w++;
    if (w == n_warps) warps[n_warps++] = g[k].eta_warp;
    int i = count[w]++;
    x[w][i] = g[k].alpha_nodes * (g[k].eta_nodes + g[k].r0_nodes);
    y[0][w][i] = fig[k][1], y[1][w][i] = fig[k][0];
  }
  bench_plot_series series[2 * MAX_GRIDS + 2];
  char labels[2 * MAX_GRIDS][64];
  int n = 0;
  double fx[2] = {1e9, 0};
  for (int w = 0; w < n_warps; w++)
    for (int i = 0; i < count[w]; i++)
      fx[0] = fmin(fx[0], x[w][i]), fx[1] = fmax(fx[1], x[w][i]);
  for (int q = 0; q < 2; q++)
    for (int w = 0; w < n_warps; w++) {
      snprintf(labels[n], sizeof labels[n], "%s, warp %g", q ? "median" : "p90", warps[w]);
      series[n] = (bench_plot_series){labels[n], count[w], x[w], y[q][w], 0, q ? w + 1 : 0};
      n++;
    }
  double fy[2][2];
  fy[0][0] = fy[0][1] = proj[1], fy[1][0] = fy[1][1] = proj[0];
  series[n++] = (bench_plot_series){"projected p90", 2, fx, fy[0], 1, 0};
  series[n++] = (bench_plot_series){"projected median", 2, fx, fy[1], 1, 0};
  bench_plot_options o = NBRDF_PLOT_OPTIONS_DEFAULT;
  o.title = "Base tables: single-set lobe error from table look-ups";
  o.x_label = "table nodes (both tables)";
  o.y_label = "lobe error %";
  o.log_x = 1;
  nbrdf_error err;
  if (bench_plot_write_png(path, &o, n, series, &err)) die(path, &err);
}

int main(int argc, char **argv) {
  const char *decoder_path = NULL, *grids_arg = "16x8x9", *csv_path = NULL, *plot_path = NULL;
  int count = 100;
  train_table_settings base = TRAIN_TABLE_SETTINGS_DEFAULT;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *v = bench_option_value(argc, argv, &i, "bench_tables", usage);
    if (!v) return 2;
    if (!strcmp(a, "--decoder"))
      decoder_path = v;
    else if (!strcmp(a, "--grids"))
      grids_arg = v;
    else if (!strcmp(a, "--csv"))
      csv_path = v;
    else if (!strcmp(a, "--count"))
      count = atoi(v);
    else if (!strcmp(a, "--steps"))
      base.steps = atoi(v);
    else if (!strcmp(a, "--plot"))
      plot_path = v;
    else {
      usage(stderr);
      return 2;
    }
  }
  if (!decoder_path || count < 1 || base.steps < 1) {
    usage(stderr);
    return 2;
  }
  train_table_settings grids[MAX_GRIDS];
  int n_grids = 0;
  char *list = strdup(grids_arg);
  for (char *tok = strtok(list, ","); tok; tok = strtok(NULL, ",")) {
    if (n_grids == MAX_GRIDS || !(grids[n_grids] = base, parse_grid(tok, &grids[n_grids]))) {
      fprintf(stderr, "bench_tables: --grids: '%s' is not AxExR[@P] (up to %d grids)\n", tok,
              MAX_GRIDS);
      return 2;
    }
    n_grids++;
  }
  free(list);

  nbrdf_error err;
  model_decoder *dec = NULL;
  if (model_decoder_load(decoder_path, &dec, &err)) die(decoder_path, &err);
  size_t n = (size_t)count, D = (size_t)dec->cfg.latent_dim;
  size_t per = (size_t)NBRDF_LOBE_N_THETA * NBRDF_LOBE_RES * NBRDF_LOBE_RES;
  double *ref = malloc(n * per * sizeof *ref), noise;
  float *lat = malloc(n * D * sizeof *lat);
  eval_case *proj = calloc(n, sizeof *proj), *tab = calloc(n, sizeof *tab);
  double *err_proj = malloc(n * sizeof *err_proj), *err_tab = malloc(n * sizeof *err_tab);
  double *added = malloc(n * sizeof *added);
  double *csv_cols = malloc(n * (size_t)n_grids * sizeof *csv_cols);
  train_params *params = malloc(n * sizeof *params);
  eval_settings es = EVAL_SETTINGS_DEFAULT;
  es.count = count, es.noise_brdfs = 0;
  uint64_t family = train_heldout_seed(TRAIN_HELDOUT_SINGLE);
  for (size_t i = 0; i < n; i++) {
    train_params_draw(family, TRAIN_SINGLE, i, &params[i]);
    proj[i].params = tab[i].params = params[i];
  }
  if (eval_reference(EVAL_SINGLE, &es, ref, &noise, &err)) die("references", &err);
  if (train_project_params(dec, n, params, family, es.project_steps, 1, lat, NULL, &err))
    die("projection", &err);
  if (eval_score_latents(dec, n, lat, ref, NULL, proj, &err)) die("projected", &err);
  for (size_t i = 0; i < n; i++)
    err_proj[i] = proj[i].lobe_error;

  printf("# Base-table interpolation error, held-out `single` set (%d BRDFs), decoder %s\n\n",
         count, decoder_path);
  char load[128];
  bench_load_line(load, sizeof load);
  printf("Projection %d steps per node; grid @P: η nodes 1.05 + 0.95·u^P, R0 nodes u^P. Lobe "
         "error %% (median / 90th pct / worst); added = table − projected, per BRDF. Load average "
         "%s.\n\n",
         base.steps, load);
  printf("| latents | nodes | fit CPU-s | all | dielectric | conductor | added, all | added, "
         "dielectric | added, conductor |\n|---|---|---|---|---|---|---|---|---|\n");
  double s[3][3], fig[MAX_GRIDS][2], proj_fig[2];
  for (int k = 0; k < 3; k++)
    stats(err_proj, proj, count, k == 0 ? -1 : k == 1 ? TRAIN_DIELECTRIC : TRAIN_CONDUCTOR, s[k]);
  printf("| projected (%d steps) | | | %.2f / %.2f / %.1f | %.2f / %.2f / %.1f | %.2f / %.2f / "
         "%.1f | | | |\n",
         es.project_steps, s[0][0], s[0][1], s[0][2], s[1][0], s[1][1], s[1][2], s[2][0], s[2][1],
         s[2][2]);
  proj_fig[0] = s[0][0], proj_fig[1] = s[0][1];
  fflush(stdout);

  for (int g = 0; g < n_grids; g++) {
    model_base_table tables[2];
    double t0 = bench_cpu_seconds();
    if (train_tables_fit(dec, &grids[g], tables, &err)) die("tables", &err);
    double fit_s = bench_cpu_seconds() - t0;
    for (size_t i = 0; i < n; i++) {
      const train_params *p = &params[i];
      int conductor = p->kind == TRAIN_CONDUCTOR;
      double p0 = p->base_alpha, p1 = conductor ? p->base_r0 : p->base_eta;
      if (model_base_table_lookup(&tables[conductor], 1, &p0, &p1, 0, lat + i * D, NULL, &err))
        die("look-up", &err);
    }
    model_base_table_free(&tables[0]);
    model_base_table_free(&tables[1]);
    if (eval_score_latents(dec, n, lat, ref, NULL, tab, &err)) die("table", &err);
    for (size_t i = 0; i < n; i++) {
      err_tab[i] = tab[i].lobe_error;
      added[i] = tab[i].lobe_error - proj[i].lobe_error;
      csv_cols[(size_t)g * n + i] = tab[i].lobe_error;
    }
    double a[3][3];
    for (int k = 0; k < 3; k++) {
      int kind = k == 0 ? -1 : k == 1 ? TRAIN_DIELECTRIC : TRAIN_CONDUCTOR;
      stats(err_tab, tab, count, kind, s[k]);
      stats(added, tab, count, kind, a[k]);
    }
    fig[g][0] = s[0][0], fig[g][1] = s[0][1];
    int nodes = grids[g].alpha_nodes * (grids[g].eta_nodes + grids[g].r0_nodes);
    printf(
        "| table %dx%dx%d@%g | %d | %.0f | %.2f / %.2f / %.1f | %.2f / %.2f / %.1f | %.2f / %.2f "
        "/ %.1f | %.2f / %.2f | %.2f / %.2f | %.2f / %.2f |\n",
        grids[g].alpha_nodes, grids[g].eta_nodes, grids[g].r0_nodes, grids[g].eta_warp, nodes,
        fit_s, s[0][0], s[0][1], s[0][2], s[1][0], s[1][1], s[1][2], s[2][0], s[2][1], s[2][2],
        a[0][0], a[0][1], a[1][0], a[1][1], a[2][0], a[2][1]);
    fflush(stdout);
  }

  if (plot_path) write_plot(plot_path, n_grids, grids, (const double(*)[2])fig, proj_fig);
  if (csv_path) {
    FILE *f = fopen(csv_path, "w");
    if (!f) {
      perror(csv_path);
      return 1;
    }
    fprintf(f, "index,kind,alpha,eta_or_r0,projected");
    for (int g = 0; g < n_grids; g++)
      fprintf(f, ",table_%dx%dx%d@%g", grids[g].alpha_nodes, grids[g].eta_nodes, grids[g].r0_nodes,
              grids[g].eta_warp);
    fprintf(f, "\n");
    for (size_t i = 0; i < n; i++) {
      const train_params *p = &params[i];
      int conductor = p->kind == TRAIN_CONDUCTOR;
      fprintf(f, "%zu,%s,%.5f,%.5f,%.5f", i, train_kind_name(p->kind), p->base_alpha,
              conductor ? p->base_r0 : p->base_eta, err_proj[i]);
      for (int g = 0; g < n_grids; g++)
        fprintf(f, ",%.5f", csv_cols[(size_t)g * n + i]);
      fprintf(f, "\n");
    }
    fclose(f);
  }
  model_decoder_destroy(dec);
  free(ref), free(lat), free(proj), free(tab), free(err_proj), free(err_tab), free(added);
  free(csv_cols), free(params);
  return 0;
}
