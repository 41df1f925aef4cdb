/* model.json's "audit_slopes" (audit_slopes.h). */
#include "model/audit_slopes.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

_Static_assert(MODEL_AUDIT_PARAMS == NBRDF_BAKE_PARAM_COUNT, "one slope per bake parameter");

enum { R = MODEL_AUDIT_REGIONS, P = MODEL_AUDIT_PARAMS };

const char *const model_audit_slopes_params[MODEL_AUDIT_PARAMS] = {"alpha1", "eta",    "alpha2",
                                                                   "r0",     "albedo", "sigma_t"};

static nbrdf_status bad(nbrdf_error *err, const char *path, const char *what) {
  return core_fail(
      err, NBRDF_ERR_FORMAT,
      "%s: \"audit_slopes\": %s (expected {\"regions\": %d, \"parameters\": [\"alpha1\", "
      "\"eta\", \"alpha2\", \"r0\", \"albedo\", \"sigma_t\"], \"table\": %d x %d x %d "
      "slopes > 0}, as `nbrdf bundle audit-slopes DIR` writes)",
      path, what, R, R, R, P);
}

nbrdf_status model_audit_slopes_read(const cJSON *root, const char *path, nbrdf_model *m,
                                     nbrdf_error *err) {
  m->has_audit_slopes = 0;
  const cJSON *o = cJSON_GetObjectItemCaseSensitive(root, "audit_slopes");
  if (!o) return NBRDF_OK;
  if (!cJSON_IsObject(o)) return bad(err, path, "not an object");
  const cJSON *regions = cJSON_GetObjectItemCaseSensitive(o, "regions");
  const cJSON *params = cJSON_GetObjectItemCaseSensitive(o, "parameters");
  const cJSON *table = cJSON_GetObjectItemCaseSensitive(o, "table");
  if (!cJSON_IsNumber(regions) || regions->valuedouble != R)
    return bad(err, path, "\"regions\" is not the audit's");
  if (!cJSON_IsArray(params) || cJSON_GetArraySize(params) != P)
    return bad(err, path, "\"parameters\" is not the list of the six");
  for (int id = 0; id < P; id++) {
    const cJSON *s = cJSON_GetArrayItem(params, id);
    if (!cJSON_IsString(s) || strcmp(s->valuestring, model_audit_slopes_params[id]) != 0)
      return bad(err, path, "\"parameters\" is not the list of the six, in order");
  }
  if (!cJSON_IsArray(table) || cJSON_GetArraySize(table) != R)
    return bad(err, path, "\"table\" does not have a row per bin of alpha1");
  for (int a = 0; a < R; a++) {
    const cJSON *row = cJSON_GetArrayItem(table, a);
    if (!cJSON_IsArray(row) || cJSON_GetArraySize(row) != R)
      return bad(err, path, "a row of \"table\" does not have an entry per bin of alpha2");
    for (int b = 0; b < R; b++) {
      const cJSON *e = cJSON_GetArrayItem(row, b);
      if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != P)
        return bad(err, path, "an entry of \"table\" does not have a slope per parameter");
      for (int id = 0; id < P; id++) {
        const cJSON *v = cJSON_GetArrayItem(e, id);
        if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble) || !(v->valuedouble > 0.0)) {
          char what[96];
          snprintf(what, sizeof what, "table[%d][%d][%d] (%s) is not a finite number > 0", a, b, id,
                   model_audit_slopes_params[id]);
          return bad(err, path, what);
        }
        m->audit_slope[a][b][id] = v->valuedouble;
      }
    }
  }
  m->has_audit_slopes = 1;
  return NBRDF_OK;
}

const double *model_audit_slopes(const nbrdf_model *m) {
  return m->has_audit_slopes ? &m->audit_slope[0][0][0] : NULL;
}
