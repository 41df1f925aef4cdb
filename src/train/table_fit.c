#include "train/table_fit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "train/checkpoint.h"
#include "train/dataset.h"
#include "train/projection.h"
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

/* The grid nodes of table t as BRDF parameters. */
static train_params *table_params(const model_base_table *t) {
  size_t n = (size_t)t->n[0] * (size_t)t->n[1];
  train_params *p = calloc(n, sizeof *p);
  if (!p) return NULL;
  for (int a = 0; a < t->n[0]; a++)
    for (int b = 0; b < t->n[1]; b++) {
      train_params *q = &p[(size_t)a * t->n[1] + b];
      q->base_alpha = t->axis[0][a];
      if (t->kind == MODEL_TABLE_DIELECTRIC)
        q->kind = TRAIN_DIELECTRIC, q->base_eta = t->axis[1][b];
      else
        q->kind = TRAIN_CONDUCTOR, q->base_r0 = t->axis[1][b];
    }
  return p;
}

/* Both tables in one trainer run: each keeps its own fit and Adam group, so
 * the latents equal those of two separate projections. */
static nbrdf_status fit_tables(model_decoder *dec, const train_table_settings *s,
                               model_base_table t[2], nbrdf_error *err) {
  train_samples data[2];
  memset(data, 0, sizeof data);
  nbrdf_status st = NBRDF_OK;
  for (int k = 0; k < 2 && !st; k++) {
    size_t n = (size_t)t[k].n[0] * (size_t)t[k].n[1];
    train_params *p = table_params(&t[k]);
    st = p ? train_samples_generate_all(&data[k], n, p, TABLE_FAMILY, err)
           : core_fail(err, NBRDF_ERR_MEMORY, "tables: out of memory");
    free(p);
    if (!st) memset(t[k].latents, 0, n * (size_t)t[k].dim * sizeof(float));
  }
  model_samples sets[2] = {train_samples_view(&data[0]), train_samples_view(&data[1])};
  float *const latents[2] = {t[0].latents, t[1].latents};
  train_projection p;
  train_project_defaults(s->steps, s->seed, &p);
  char options[1024] = "";
  trainer_option(options, sizeof options, "nodes", "alpha %d, eta %d, r0 %d", s->alpha_nodes,
                 s->eta_nodes, s->r0_nodes);
  trainer_option(options, sizeof options, "warps", "eta %.9g, r0 %.9g", s->eta_warp, s->r0_warp);
  if (s->eta_min != 1.05) /* absent at the default: checkpoints from before it still match */
    trainer_option(options, sizeof options, "eta-min", "%.9g", s->eta_min);
  trainer_option(options, sizeof options, "decoder weights", "%016llx",
                 (unsigned long long)train_hash_floats(TRAIN_HASH_START, nn_params_const(dec->nn),
                                                       nn_param_count(dec->nn)));
  trainer_options to = TRAINER_OPTIONS_DEFAULT;
  to.format = "nbrdf-train-tables-checkpoint";
  to.options = options;
  to.stage = "tables";
  to.progress = s->progress, to.user = s->user, to.cancel = s->cancel;
  to.checkpoint = s->checkpoint, to.checkpoint_seconds = s->checkpoint_seconds;
  to.max_seconds = s->max_seconds, to.stop_at_step = s->stop_at_step;
  if (!st) st = train_project_sets(dec, 2, sets, latents, &p, &to, NULL, err);
  train_samples_free(&data[0]);
  train_samples_free(&data[1]);
  return st;
}

nbrdf_status train_tables_fit(model_decoder *dec, const train_table_settings *s,
                              model_base_table tables[2], nbrdf_error *err) {
  if (s->alpha_nodes < 2 || s->eta_nodes < 2 || s->r0_nodes < 2 || s->steps < 1 ||
      !(s->eta_warp >= 0.25 && s->eta_warp <= 4) || !(s->r0_warp >= 0.25 && s->r0_warp <= 4) ||
      !(s->eta_min >= 1.0 && s->eta_min <= 1.9))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "tables: >= 2 nodes per axis, >= 1 step, warps in [0.25, 4] and the first "
                     "eta node in [1, 1.9]");
  int na = s->alpha_nodes, D = dec->cfg.latent_dim;
  float *alpha = malloc((size_t)na * sizeof *alpha);
  float *eta = malloc((size_t)s->eta_nodes * sizeof *eta);
  float *r0 = malloc((size_t)s->r0_nodes * sizeof *r0);
  nbrdf_status st =
      alpha && eta && r0 ? NBRDF_OK : core_fail(err, NBRDF_ERR_MEMORY, "tables: out of memory");
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
  if (!st) st = fit_tables(dec, s, tables, err);
  free(alpha), free(eta), free(r0);
  if (st) {
    model_base_table_free(&tables[0]);
    model_base_table_free(&tables[1]);
  }
  return st;
}
