/* `nbrdf evaluate` output: the JSON summary and lobe plots. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "core/output_file.h"
#include "eval/evaluate.h"
#include "lobe/lobe.h"
#include "lobe/lobe_png.h"

#define PER_BRDF ((size_t)NBRDF_LOBE_N_THETA * NBRDF_LOBE_RES * NBRDF_LOBE_RES)

/* The parameters as JSON members. */
static void params_json(FILE *f, const train_params *p) {
  fprintf(f, "{\"kind\": \"%s\"", train_kind_name(p->kind));
  for (int c = 0; c < p->n_coats; c++)
    fprintf(f,
            ", \"coat%d\": {\"alpha\": %.5g, \"eta\": %.5g, \"albedo\": %.5g, \"sigma_t\": %.5g}",
            c, p->coat[c].alpha, p->coat[c].eta, p->coat[c].albedo, p->coat[c].sigma_t);
  if (p->kind == TRAIN_DIELECTRIC)
    fprintf(f, ", \"alpha\": %.5g, \"eta\": %.5g}", p->base_alpha, p->base_eta);
  else
    fprintf(f, ", \"alpha\": %.5g, \"r0\": %.5g}", p->base_alpha, p->base_r0);
}

/* A JSON number, or null for NaN/Inf (JSON has neither). */
static void num(FILE *f, double v) {
  if (isfinite(v))
    fprintf(f, "%.6g", v);
  else
    fputs("null", f);
}

/* A median's 90 % interval as a JSON pair of numbers. */
static void interval(FILE *f, double lo, double hi) {
  fputc('[', f), num(f, lo), fputs(", ", f), num(f, hi), fputc(']', f);
}

static void array(FILE *f, const char *key, const double *v, int n) {
  fprintf(f, "      \"%s\": [", key);
  for (int t = 0; t < n; t++) {
    if (t) fputs(", ", f);
    num(f, v[t]);
  }
  fputs("],\n", f);
}

/* Every case's decoded (reference = 0) or reference albedo per angle: a
 * JSON array of arrays, without the brackets around it. */
static void albedos(FILE *f, const eval_result *x, int reference) {
  for (int i = 0; i < x->n; i++) {
    const double *a = reference ? x->cases[i].albedo_ref : x->cases[i].albedo;
    fputs(i ? ", [" : "[", f);
    for (int k = 0; k < EVAL_N_THETA_ALL; k++) {
      if (k) fputs(", ", f);
      num(f, a[k]);
    }
    fputs("]", f);
  }
}

/* The point-wise, mirror and decoded-albedo figures (evaluate_grazing.c). */
static void extra_json(FILE *f, const eval_result *x) {
  array(f, "theta_deg", eval_theta_all_deg, EVAL_N_THETA_ALL);
  fputs("      \"median_pointwise_error\": ", f);
  num(f, x->median_pointwise_all);
  fputs(",\n", f);
  array(f, "median_pointwise_error_per_theta", x->median_pointwise, EVAL_N_THETA_ALL);
  array(f, "median_mirror_error_per_theta", x->median_mirror, EVAL_N_THETA_ALL);
  array(f, "max_decoded_albedo_per_theta", x->max_decoded_albedo, EVAL_N_THETA_ALL);
  array(f, "max_decoded_albedo_excess_per_theta", x->max_albedo_excess, EVAL_N_THETA_ALL);
  const eval_case *c = &x->cases[x->max_decoded_albedo_index];
  int t = x->max_decoded_albedo_theta;
  fprintf(f, "      \"max_decoded_albedo_brdf\": {\"index\": %d, \"theta_deg\": %g, \"decoded\": ",
          x->max_decoded_albedo_index, eval_theta_all_deg[t]);
  num(f, c->albedo[t]);
  fputs(", \"reference\": ", f);
  num(f, c->albedo_ref[t]);
  fputs(", \"reference_se\": ", f);
  num(f, c->albedo_ref_se[t]);
  fputs(", \"params\": ", f);
  params_json(f, &c->params);
  fputs("},\n      \"pointwise_errors\": [", f);
  for (int i = 0; i < x->n; i++) {
    if (i) fputs(", ", f);
    num(f, x->cases[i].pointwise_all);
  }
  fputs("],\n      \"decoded_albedo\": [", f);
  albedos(f, x, 0);
  fputs("],\n      \"reference_albedo\": [", f);
  albedos(f, x, 1);
  fputs("],\n", f);
}

nbrdf_status eval_write_json(const char *path, const char *model_label, const eval_settings *s,
                             const eval_result *r, int n_results, nbrdf_error *err) {
  char *text = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&text, &len); /* written whole by the output module */
  if (!f) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  fprintf(f, "{\n  \"model\": \"%s\",\n  \"count\": %d,\n  \"reference_walks\": %d,\n", model_label,
          s->count, s->walks);
  fprintf(f, "  \"projection_steps\": %d,\n  \"sets\": {", s->project_steps);
  for (int k = 0; k < n_results; k++) {
    const eval_result *x = &r[k];
    fprintf(f, "%s\n    \"%s\": {\n", k ? "," : "", eval_set_name(x->set));
    fprintf(f, "      \"median_lobe_error\": %.6g,\n      \"p90_lobe_error\": %.6g,\n", x->median,
            x->p90);
    fputs("      \"median_interval90\": ", f);
    interval(f, x->median_lo, x->median_hi);
    fputs(",\n", f);
    fprintf(f, "      \"median_albedo_error\": %.6g,\n      \"max_albedo\": %.6g,\n",
            x->median_albedo_error, x->max_albedo);
    fprintf(f, "      \"reference_noise\": %.6g,\n", x->ref_noise);
    fprintf(f, "      \"seconds_reference\": %.1f,\n      \"seconds_model\": %.1f,\n",
            x->seconds_reference, x->seconds_model);
    fprintf(f,
            "      \"worst\": {\"index\": %d, \"lobe_error\": %.6g, \"params\": ", x->worst_index,
            x->worst);
    params_json(f, &x->cases[x->worst_index].params);
    fprintf(f, "},\n      \"max_albedo_brdf\": {\"index\": %d, \"params\": ", x->max_albedo_index);
    params_json(f, &x->cases[x->max_albedo_index].params);
    fprintf(f, "},\n");
    if (eval_set_has_regions(x->set)) {
      fputs("      \"regions\": {", f);
      for (int g = 0; g < TRAIN_TAILS_REGIONS; g++) {
        fprintf(f,
                "%s\"%s\": {\"count\": %d, \"median_lobe_error\": %.6g, \"p90_lobe_error\": %.6g, "
                "\"median_interval90\": ",
                g ? ", " : "", train_tails_region_name(g), x->region_n[g], x->region_median[g],
                x->region_p90[g]);
        interval(f, x->region_median_lo[g], x->region_median_hi[g]);
        fputc('}', f);
      }
      fputs("},\n", f);
    }
    if (x->set == EVAL_EXTREMES) {
      fputs("      \"case_names\": [", f);
      for (int i = 0; i < x->n; i++)
        fprintf(f, "%s\"%s\"", i ? ", " : "", eval_extremes_name(i));
      fputs("],\n", f);
    }
    extra_json(f, x);
    fprintf(f, "      \"lobe_errors\": [");
    for (int i = 0; i < x->n; i++)
      fprintf(f, "%s%.5g", i ? ", " : "", x->cases[i].lobe_error);
    fprintf(f, "]\n    }");
  }
  fprintf(f, "\n  }\n}\n");
  int bad = ferror(f) | fclose(f);
  nbrdf_status st = bad ? core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path)
                        : core_output_file_write_all(path, text, len, NULL, 0, err);
  free(text);
  return st;
}

nbrdf_status eval_write_plots(const char *dir, const eval_result *r, int n_results,
                              nbrdf_error *err) {
  if (mkdir(dir, 0777) != 0 && errno != EEXIST)
    return core_fail(err, NBRDF_ERR_IO, "%s: cannot create: %s", dir, strerror(errno));
  nbrdf_status st = NBRDF_OK;
  for (int k = 0; k < n_results && !st; k++) {
    const char *what[2] = {"median", "worst"};
    int idx[2] = {r[k].median_index, r[k].worst_index};
    for (int j = 0; j < 2 && !st; j++) {
      char path[4096];
      snprintf(path, sizeof path, "%s/%s_%s.png", dir, eval_set_name(r[k].set), what[j]);
      size_t at = (size_t)idx[j] * PER_BRDF;
      st = lobe_write_png(path, NBRDF_LOBE_RES, NBRDF_LOBE_N_THETA, r[k].ref + at, r[k].approx + at,
                          2, err);
    }
  }
  return st;
}
