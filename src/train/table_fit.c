#include "train/table_fit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/progress.h"
#include "model/autodecoder.h"
#include "train/dataset.h"
#include "train/samples.h"

/* Node streams for the sample generator: any fixed family apart from the
 * training and held-out ones. */
#define TABLE_FAMILY UINT64_C(0x6e62726474626c73)

static void alpha_axis(float *a, int n) {
  for (int i = 0; i < n; i++) {
    double u = 0.216 + (1.0 - 0.216) * i / (n - 1);
    a[i] = (float)(u * u * u);
  }
  a[0] = 0.01f, a[n - 1] = 1.0f;
}

/* lo + (hi − lo)·u^warp at u uniform in [0, 1]. */
static void warped_space(float *x, int n, double lo, double hi, double warp) {
  for (int i = 0; i < n; i++)
    x[i] = (float)(lo + (hi - lo) * pow((double)i / (n - 1), warp));
}

static nbrdf_status fit_table(model_decoder *dec, const train_table_settings *s,
                              model_base_table *t, const train_project_progress *progress,
                              nbrdf_error *err) {
  size_t n = (size_t)t->n[0] * (size_t)t->n[1];
  train_params *p = calloc(n, sizeof *p);
  if (!p) return nbrdf_fail(err, NBRDF_ERR_MEMORY, "tables: out of memory");
  for (int a = 0; a < t->n[0]; a++)
    for (int b = 0; b < t->n[1]; b++) {
      train_params *q = &p[(size_t)a * t->n[1] + b];
      q->base_alpha = t->axis[0][a];
      if (t->kind == MODEL_TABLE_DIELECTRIC)
        q->kind = TRAIN_DIELECTRIC, q->base_eta = t->axis[1][b];
      else
        q->kind = TRAIN_CONDUCTOR, q->base_r0 = t->axis[1][b];
    }
  nbrdf_status st =
      train_project_params(dec, n, p, TABLE_FAMILY, s->steps, s->seed, t->latents, progress, err);
  free(p);
  return st;
}

nbrdf_status train_tables_fit(model_decoder *dec, const train_table_settings *s,
                              model_base_table tables[2], nbrdf_error *err) {
  if (s->alpha_nodes < 2 || s->eta_nodes < 2 || s->r0_nodes < 2 || s->steps < 1 ||
      !(s->eta_warp >= 0.25 && s->eta_warp <= 4) || !(s->r0_warp >= 0.25 && s->r0_warp <= 4) ||
      !(s->eta_min >= 1.0 && s->eta_min <= 1.9))
    return nbrdf_fail(err, NBRDF_ERR_ARGUMENT,
                      "tables: >= 2 nodes per axis, >= 1 step, warps in [0.25, 4] and the first "
                      "eta node in [1, 1.9]");
  int na = s->alpha_nodes, D = dec->cfg.latent_dim;
  float *alpha = malloc((size_t)na * sizeof *alpha);
  float *eta = malloc((size_t)s->eta_nodes * sizeof *eta);
  float *r0 = malloc((size_t)s->r0_nodes * sizeof *r0);
  nbrdf_status st =
      alpha && eta && r0 ? NBRDF_OK : nbrdf_fail(err, NBRDF_ERR_MEMORY, "tables: out of memory");
  memset(tables, 0, 2 * sizeof *tables);
  if (!st) {
    alpha_axis(alpha, na);
    warped_space(eta, s->eta_nodes, s->eta_min, 2.0, s->eta_warp);
    warped_space(r0, s->r0_nodes, 0.0, 1.0, s->r0_warp);
    st = model_base_table_init(&tables[0], MODEL_TABLE_DIELECTRIC, D, na, alpha, s->eta_nodes, eta,
                               err);
  }
  if (!st)
    st = model_base_table_init(&tables[1], MODEL_TABLE_CONDUCTOR, D, na, alpha, s->r0_nodes, r0,
                               err);
  /* progress per step of the two fits (a table of 16 x 9 nodes takes ~0.1 s a step) */
  nbrdf_ticker tk;
  nbrdf_ticker_init(&tk, s->progress, s->user, NULL);
  for (int k = 0; k < 2 && !st; k++) {
    train_project_progress pp = {&tk, "tables", (double)k * s->steps, 2.0 * s->steps};
    if (nbrdf_ticker_tick(&tk, "tables", pp.done0, pp.total, k == 0))
      st = nbrdf_fail(err, NBRDF_ERR_CANCELLED, "tables: cancelled");
    else
      st = fit_table(dec, s, &tables[k], &pp, err);
  }
  if (!st && nbrdf_ticker_tick(&tk, "tables", 2.0 * s->steps, 2.0 * s->steps, 1))
    st = nbrdf_fail(err, NBRDF_ERR_CANCELLED, "tables: cancelled");
  free(alpha), free(eta), free(r0);
  if (st) {
    model_base_table_free(&tables[0]);
    model_base_table_free(&tables[1]);
  }
  return st;
}
