#include "cli/eval_neural.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bake/bake_tuple.h"
#include "cli/cli.h"
#include "core/error.h"
#include "nbrdf/model.h"

/* Rows go through the networks this many at a time, so memory stays bounded. */
#define EVAL_NEURAL_CHUNK 16384

/* The bake parameter each column of a kind stands for. */
static const int LAYERED_IDS[6] = {NBRDF_BAKE_ALPHA1, NBRDF_BAKE_ETA,    NBRDF_BAKE_ALPHA2,
                                   NBRDF_BAKE_R0,     NBRDF_BAKE_ALBEDO, NBRDF_BAKE_SIGMA_T};
static const int CONDUCTOR_IDS[2] = {NBRDF_BAKE_ALPHA2, NBRDF_BAKE_R0};
static const int DIELECTRIC_IDS[2] = {NBRDF_BAKE_ALPHA1, NBRDF_BAKE_ETA};

/* Row k's parameters through the bake's conventions into t (a full tuple;
 * columns a kind does not have keep a value inside the range). */
static int prepare_row(const cli_eval_neural_options *o, const float *lo, const float *hi,
                       cli_eval_neural_kind kind, const double *v, const char *const *columns,
                       size_t line, bake_tuple *t) {
  const int *ids = kind == CLI_EVAL_NEURAL_LAYERED     ? LAYERED_IDS
                   : kind == CLI_EVAL_NEURAL_CONDUCTOR ? CONDUCTOR_IDS
                                                       : DIELECTRIC_IDS;
  int np = kind == CLI_EVAL_NEURAL_LAYERED ? 6 : 2;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    t->p[id] = lo[id];
  for (int c = 0; c < np; c++) {
    int id = ids[c];
    float x = (float)v[c], read = x;
    model_material_verdict verdict =
        model_material_prepare(lo, hi, id, o->roughness, o->range, &x, &read);
    if (verdict > MODEL_VALUE_CLAMPED) {
      char at[160];
      nbrdf_error err = {0};
      snprintf(at, sizeof at, "line %zu, column '%s'", line, columns[c]);
      model_material_fail(verdict, lo, hi, id, o->roughness, at, (float)v[c], &err);
      return cli_fail_error("eval", &err);
    }
    if (verdict == MODEL_VALUE_CLAMPED) {
      char what[48], msg[256];
      snprintf(what, sizeof what, "%g", (double)read);
      model_material_clamp_warning(msg, sizeof msg, columns[c], lo, hi, id, what, 0);
      fprintf(stderr, "nbrdf eval: warning: line %zu: %s to %g\n", line, msg, (double)x);
    }
    t->p[id] = x;
  }
  return CLI_EXIT_OK;
}

/* f of rows [k0, k0 + m): the bake's tuple evaluation (or, for the base
 * BRDFs alone, its table look-up), then the decoder. */
static nbrdf_status run_chunk(const nbrdf_model *model, cli_eval_neural_kind kind,
                              const bake_tuple *t, size_t m, const nbrdf_query *q, float *scratch,
                              double *f, nbrdf_error *err) {
  const size_t D = (size_t)nbrdf_model_latent_dim(model);
  float *tuple_out = scratch, *lat = tuple_out + m * (D + 2), *wi = lat + m * D, *wo = wi + 3 * m,
        *out = wo + 3 * m;
  float *p0 = malloc(sizeof(float) * 2 * m);
  if (!p0) return core_fail(err, NBRDF_ERR_MEMORY, "eval: out of memory");
  nbrdf_status st = NBRDF_OK;
  if (kind == CLI_EVAL_NEURAL_LAYERED) {
    st = bake_tuples_evaluate(model, t, NULL, m, tuple_out, err);
    for (size_t k = 0; st == NBRDF_OK && k < m; k++)
      memcpy(lat + k * D, tuple_out + k * (D + 2), sizeof(float) * D);
  } else {
    int a = kind == CLI_EVAL_NEURAL_CONDUCTOR ? NBRDF_BAKE_ALPHA2 : NBRDF_BAKE_ALPHA1;
    int b = kind == CLI_EVAL_NEURAL_CONDUCTOR ? NBRDF_BAKE_R0 : NBRDF_BAKE_ETA;
    for (size_t k = 0; k < m; k++)
      p0[k] = t[k].p[a], p0[m + k] = t[k].p[b];
    st = nbrdf_model_base_latents(
        model, kind == CLI_EVAL_NEURAL_CONDUCTOR ? NBRDF_BASE_CONDUCTOR : NBRDF_BASE_DIELECTRIC, m,
        p0, p0 + m, NBRDF_RANGE_CLAMP, lat, NULL, err);
  }
  for (size_t k = 0; k < m; k++)
    for (int j = 0; j < 3; j++)
      wi[3 * k + j] = (float)q[k].wi[j], wo[3 * k + j] = (float)q[k].wo[j];
  if (st == NBRDF_OK) st = nbrdf_model_decode(model, m, 1, lat, wi, wo, out, err);
  for (size_t k = 0; st == NBRDF_OK && k < m; k++)
    f[k] = out[k];
  free(p0);
  return st;
}

int cli_eval_neural(const cli_eval_neural_options *o, cli_eval_neural_kind kind, size_t n,
                    const double *params, const char *const *columns, const nbrdf_query *q,
                    const size_t *lines, double *f) {
  char bundle[PATH_MAX];
  nbrdf_error err = {0};
  nbrdf_model *m = NULL;
  int loaded = cli_model_load("eval", o->bundle, &m, bundle, sizeof bundle);
  if (loaded != CLI_EXIT_OK) return loaded;
  if (!nbrdf_model_is_trained(m))
    fprintf(stderr, "nbrdf eval: warning: bundle '%s' is untrained (random networks)\n", bundle);
  float lo[NBRDF_BAKE_PARAM_COUNT], hi[NBRDF_BAKE_PARAM_COUNT];
  model_material_ranges(m, lo, hi);
  const size_t D = (size_t)nbrdf_model_latent_dim(m), np = kind == CLI_EVAL_NEURAL_LAYERED ? 6 : 2;
  const size_t chunk = n < EVAL_NEURAL_CHUNK ? n : EVAL_NEURAL_CHUNK;
  bake_tuple *t = malloc(sizeof *t * (n ? n : 1));
  float *scratch = malloc(sizeof(float) * chunk * (2 * D + 2 + 7));
  int rc = t && scratch ? CLI_EXIT_OK : cli_fail("eval", "out of memory for %zu rows", n);
  for (size_t k = 0; k < n && rc == CLI_EXIT_OK; k++)
    rc = prepare_row(o, lo, hi, kind, params + k * np, columns, lines[k], &t[k]);
  for (size_t k = 0; k < n && rc == CLI_EXIT_OK; k += chunk) {
    size_t len = n - k < chunk ? n - k : chunk;
    if (run_chunk(m, kind, t + k, len, q + k, scratch, f + k, &err) != NBRDF_OK)
      rc = cli_fail_error("eval", &err);
  }
  free(t);
  free(scratch);
  nbrdf_model_destroy(m);
  return rc;
}
