/* nbrdf evaluate's machinery on a small untrained decoder: each case's figures
 * are those of its stored images, the summary statistics are those of the
 * cases, references come back identical from the cache, the layering sets
 * need a bundle, and the JSON report is written. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "eval/evaluate.h"
#include "lobe/lobe.h"
#include "model/bundle.h"
#include "testing.h"

#define PER ((size_t)NBRDF_LOBE_N_THETA * NBRDF_LOBE_RES * NBRDF_LOBE_RES)

static void test_single_set(void) {
  nbrdf_error err;
  model_decoder_config cfg;
  model_decoder *dec = NULL;
  CHECK_OK(model_decoder_preset("small", 32, &cfg, &err), &err);
  CHECK_OK(model_decoder_create(&cfg, 7, &dec, &err), &err);
  if (!dec) return;
  char cache[512], json[512];
  snprintf(cache, sizeof cache, "%s/cache", testing_tmpdir());
  snprintf(json, sizeof json, "%s/eval.json", testing_tmpdir());
  eval_settings s = EVAL_SETTINGS_DEFAULT;
  s.count = 5, s.project_steps = 5, s.cache_dir = cache;
  eval_result r;
  CHECK_OK(eval_run(NULL, dec, EVAL_SINGLE, &s, &r, &err), &err);
  if (!r.cases) return;
  int worse_than_median = 0;
  for (int i = 0; i < r.n; i++) {
    double e = lobe_l1_error(PER, r.ref + i * PER, r.approx + i * PER);
    CHECK_NEAR(r.cases[i].lobe_error, e, 1e-12);
    CHECK(r.cases[i].lobe_error <= r.worst);
    worse_than_median += r.cases[i].lobe_error > r.median;
  }
  CHECK(r.worst == r.cases[r.worst_index].lobe_error);
  CHECK(r.median == r.cases[r.median_index].lobe_error);
  CHECK(worse_than_median == r.n / 2 - (r.n % 2 == 0)); /* median = element n/2 of the sorted */
  CHECK(r.ref_noise == 0.0);                            /* single BRDFs are exact */

  /* The cache returns the references (stored as float). */
  double *again = malloc((size_t)s.count * PER * sizeof *again), noise = -1;
  CHECK_OK(eval_reference(EVAL_SINGLE, &s, again, &noise, &err), &err);
  double worst_diff = 0;
  for (size_t k = 0; k < (size_t)s.count * PER; k++) {
    double d = fabs(again[k] - r.ref[k]) / (fabs(r.ref[k]) + 1e-30);
    if (r.ref[k] != 0 && d > worst_diff) worst_diff = d;
  }
  CHECK_MSG(worst_diff < 1e-6, "cached reference differs by %g", worst_diff);
  free(again);

  CHECK_OK(eval_write_json(json, "test", &s, &r, 1, &err), &err);
  FILE *f = fopen(json, "r");
  char buf[4096] = {0};
  if (f) {
    size_t got = fread(buf, 1, sizeof buf - 1, f);
    buf[got] = '\0';
    fclose(f);
  }
  CHECK(strstr(buf, "\"single\"") && strstr(buf, "\"median_lobe_error\""));
  /* the median's interval brackets it and is written beside it */
  CHECK(r.median_lo <= r.median && r.median <= r.median_hi);
  CHECK(strstr(buf, "\"median_interval90\": ["));
  CHECK(strstr(buf, "\"median_pointwise_error\"") &&
        strstr(buf, "\"max_decoded_albedo_per_theta\""));

  /* The figures of issue 18: point-wise errors of the four standard images
   * are those of the stored images; the single set's reference albedo and
   * mirror values are exact (analytic BRDFs), so the extra cache returns them. */
  for (int i = 0; i < r.n; i++) {
    const eval_case *c = &r.cases[i];
    for (int t = 0; t < NBRDF_LOBE_N_THETA; t++) {
      size_t at = i * PER + (size_t)t * NBRDF_LOBE_RES * NBRDF_LOBE_RES;
      double e = lobe_pointwise_error(NBRDF_LOBE_RES, r.ref + at, r.approx + at, 0.01);
      CHECK_NEAR(c->pointwise[t], e, 1e-6 * (e + 1e-30));
    }
    for (int t = 0; t < EVAL_N_THETA_ALL; t++) {
      CHECK(isfinite(c->albedo[t]) && c->albedo[t] >= 0.0);
      CHECK(c->albedo_ref[t] > 0.0 && c->albedo_ref[t] <= 1.0 + 4.0 * c->albedo_ref_se[t]);
      CHECK(c->albedo[t] <= r.max_decoded_albedo[t]);
    }
    CHECK(isfinite(c->pointwise_all) && c->pointwise_all >= 0.0);
  }
  eval_extra_ref x;
  CHECK_OK(eval_reference_extra(EVAL_SINGLE, &s, &x, &err), &err);
  if (x.albedo) {
    for (int i = 0; i < r.n; i++)
      for (int t = 0; t < EVAL_N_THETA_ALL; t++)
        CHECK_REL(x.albedo[i * EVAL_N_THETA_ALL + t], r.cases[i].albedo_ref[t], 1e-6, 1e-9);
    eval_extra_ref_free(&x);
  }

  /* The table set: the same BRDFs (the same references), latents from a bundle's tables. */
  char dir[512];
  snprintf(dir, sizeof dir, "%s/bundle", testing_tmpdir());
  nbrdf_model *m = NULL;
  CHECK_OK(model_bundle_init_random(dir, "eval-test", 3, "small", &err), &err);
  CHECK_OK(nbrdf_model_load(dir, &m, &err), &err);
  eval_result tr;
  if (m) {
    CHECK_OK(eval_run(m, NULL, EVAL_TABLE, &s, &tr, &err), &err);
    if (tr.cases) {
      double d = 0; /* (from the cache: float) */
      for (size_t k = 0; k < (size_t)s.count * PER; k++)
        d = fmax(d, fabs(tr.ref[k] - r.ref[k]) / (fabs(r.ref[k]) + 1e-30));
      CHECK_MSG(d < 1e-6, "table references differ from single's by %g", d);
      CHECK(!strcmp(eval_set_name(tr.set), "table") && tr.n == s.count && tr.worst > 0);
      eval_result_free(&tr);
    }
  }
  /* The tails set: layered references (few walks: this checks the bookkeeping, not a figure),
   * region figures of the cases i % 3, drawn where the set says. */
  eval_settings ts = s;
  ts.count = 6, ts.walks = 64, ts.noise_brdfs = 0, ts.cache_dir = NULL;
  if (m) {
    CHECK_OK(eval_run(m, NULL, EVAL_TAILS, &ts, &tr, &err), &err);
    if (tr.cases) {
      CHECK(!strcmp(eval_set_name(tr.set), "tails") && tr.n == 6);
      for (int g = 0; g < TRAIN_TAILS_REGIONS; g++) {
        CHECK(tr.region_n[g] == 2);
        double a = tr.cases[g].lobe_error, b = tr.cases[g + 3].lobe_error;
        CHECK_NEAR(tr.region_median[g], fmax(a, b), 1e-12); /* median of two: the upper */
        CHECK(tr.region_p90[g] == tr.region_median[g]);
      }
      CHECK(tr.cases[0].params.coat[0].eta <= 1.2 && tr.cases[1].params.coat[0].alpha <= 0.05);
      /* tails-rep: the same BRDFs and references, projected by a decoder alone, with regions. */
      eval_result rr;
      CHECK_OK(eval_run(NULL, dec, EVAL_TAILS_REP, &ts, &rr, &err), &err);
      if (rr.cases) {
        CHECK(!strcmp(eval_set_name(rr.set), "tails-rep") && rr.region_n[2] == 2);
        CHECK(!memcmp(rr.ref, tr.ref, (size_t)ts.count * PER * sizeof *rr.ref));
        CHECK(rr.cases[5].params.coat[0].alpha == tr.cases[5].params.coat[0].alpha);
        eval_result_free(&rr);
      }
      eval_result_free(&tr);
    }
  }
  nbrdf_model_destroy(m);
  eval_result_free(&r);

  /* extremes: fixed named cases, as many as there are. */
  train_params xp;
  eval_set_draw(EVAL_EXTREMES, 0, &xp);
  CHECK(xp.kind == TRAIN_LAYERED2 && xp.coat[0].alpha == 0.01 && xp.coat[0].eta == 1.5 &&
        xp.base_r0 == 1.0 && xp.base_alpha == 0.01);
  CHECK(strstr(eval_extremes_name(0), "mirror") && eval_set_size_max(EVAL_EXTREMES) == 9);
  eval_result none;
  CHECK_FAILS(eval_run(NULL, dec, EVAL_LAYER, &s, &none, &err), NBRDF_ERR_ARGUMENT, &err,
              "needs a bundle");
  CHECK_FAILS(eval_run(NULL, dec, EVAL_TABLE, &s, &none, &err), NBRDF_ERR_ARGUMENT, &err,
              "needs a bundle");
  CHECK_FAILS(eval_run(NULL, dec, EVAL_TAILS, &s, &none, &err), NBRDF_ERR_ARGUMENT, &err,
              "needs a bundle");
  eval_settings many = s;
  many.count = 12;
  CHECK_FAILS(eval_run(NULL, dec, EVAL_EXTREMES, &many, &none, &err), NBRDF_ERR_ARGUMENT, &err,
              "has 9 BRDFs");
  CHECK_FAILS(eval_run(NULL, dec, EVAL_EXTREMES, &s, &none, &err), NBRDF_ERR_ARGUMENT, &err,
              "needs a bundle");
  model_decoder_destroy(dec);
}

static int stop_inside_first(void *user, const char *stage, double done, double total) {
  (void)stage, (void)total;
  *(int *)user += 1;
  return done < 1.0; /* before the first BRDF's references are done */
}

/* Ctrl-C (the callback's answer) reaches inside one layered BRDF's
 * references: a layered reference takes seconds of random walks. */
static void test_reference_cancel(void) {
  nbrdf_error err;
  eval_settings s = EVAL_SETTINGS_DEFAULT;
  int calls = 0;
  s.count = 3, s.walks = 200000, s.cache_dir = NULL;
  s.progress = stop_inside_first, s.user = &calls;
  double *images = malloc((size_t)s.count * PER * sizeof *images), noise;
  CHECK_FAILS(eval_reference(EVAL_LAYER, &s, images, &noise, &err), NBRDF_ERR_CANCELLED, &err,
              "cancelled");
  CHECK(calls == 1);
  free(images);
}

int main(void) {
  RUN(test_single_set);
  RUN(test_reference_cancel);
  return testing_finish();
}
