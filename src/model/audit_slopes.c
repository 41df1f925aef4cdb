/* model.json's "audit_slopes" (audit_slopes.h). */
#include "model/audit_slopes.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

_Static_assert(MODEL_AUDIT_PARAMS == NBRDF_BAKE_PARAM_COUNT, "one slope per bake parameter");

enum { R = MODEL_AUDIT_REGIONS, P = MODEL_AUDIT_PARAMS, DIRS = MODEL_AUDIT_DIRS };

const char *const model_audit_slopes_params[MODEL_AUDIT_PARAMS] = {"alpha1", "eta",    "alpha2",
                                                                   "r0",     "albedo", "sigma_t"};

static nbrdf_status bad(nbrdf_error *err, const char *path, const char *what) {
  return core_fail(
      err, NBRDF_ERR_FORMAT,
      "%s: \"audit_slopes\": %s (expected {\"regions\": %d, \"parameters\": [\"alpha1\", "
      "\"eta\", \"alpha2\", \"r0\", \"albedo\", \"sigma_t\"], \"directions\": [\"up\", "
      "\"down\"], \"table\": %d x %d x %d x %d slopes > 0}, as `nbrdf bundle audit-slopes DIR` "
      "writes)",
      path, what, R, R, R, P, DIRS);
}

static int is_list(const cJSON *x, int n) { return cJSON_IsArray(x) && cJSON_GetArraySize(x) == n; }

/* One entry's six slopes: [up, down] pairs (split), or numbers for both ways. */
static nbrdf_status read_entry(const cJSON *e, int split, const char *path, int a, int b,
                               double (*out)[DIRS], nbrdf_error *err) {
  if (!is_list(e, P))
    return bad(err, path, "an entry of \"table\" does not have a slope per parameter");
  for (int id = 0; id < P; id++) {
    const cJSON *v = cJSON_GetArrayItem(e, id);
    if (split && !is_list(v, DIRS))
      return bad(err, path, "an entry of \"table\" does not have an [up, down] pair per parameter");
    if (!split && cJSON_IsArray(v))
      return bad(err, path, "an entry of \"table\" has pairs but \"directions\" is absent");
    for (int dir = 0; dir < DIRS; dir++) {
      const cJSON *x = split ? cJSON_GetArrayItem(v, dir) : v;
      if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble) || !(x->valuedouble > 0.0)) {
        char what[128];
        if (split)
          snprintf(what, sizeof what, "table[%d][%d][%d][%d] (%s, %s) is not a finite number > 0",
                   a, b, id, dir, model_audit_slopes_params[id], dir ? "down" : "up");
        else
          snprintf(what, sizeof what, "table[%d][%d][%d] (%s) is not a finite number > 0", a, b, id,
                   model_audit_slopes_params[id]);
        return bad(err, path, what);
      }
      out[id][dir] = x->valuedouble;
    }
  }
  return NBRDF_OK;
}

nbrdf_status model_audit_slopes_read(const cJSON *root, const char *path, nbrdf_model *m,
                                     nbrdf_error *err) {
  m->has_audit_slopes = 0;
  m->audit_slopes_both_ways = 0;
  const cJSON *o = cJSON_GetObjectItemCaseSensitive(root, "audit_slopes");
  if (!o) return NBRDF_OK;
  if (!cJSON_IsObject(o)) return bad(err, path, "not an object");
  const cJSON *regions = cJSON_GetObjectItemCaseSensitive(o, "regions");
  const cJSON *params = cJSON_GetObjectItemCaseSensitive(o, "parameters");
  const cJSON *table = cJSON_GetObjectItemCaseSensitive(o, "table");
  if (!cJSON_IsNumber(regions) || regions->valuedouble != R)
    return bad(err, path, "\"regions\" is not the audit's");
  if (!is_list(params, P)) return bad(err, path, "\"parameters\" is not the list of the six");
  for (int id = 0; id < P; id++) {
    const cJSON *s = cJSON_GetArrayItem(params, id);
    if (!cJSON_IsString(s) || strcmp(s->valuestring, model_audit_slopes_params[id]) != 0)
      return bad(err, path, "\"parameters\" is not the list of the six, in order");
  }
  /* The second form names the directions; the first has one number both ways. */
  const cJSON *dirs = cJSON_GetObjectItemCaseSensitive(o, "directions");
  int split = dirs != NULL;
  if (split && (!is_list(dirs, DIRS) || !cJSON_IsString(cJSON_GetArrayItem(dirs, 0)) ||
                !cJSON_IsString(cJSON_GetArrayItem(dirs, 1)) ||
                strcmp(cJSON_GetArrayItem(dirs, 0)->valuestring, "up") != 0 ||
                strcmp(cJSON_GetArrayItem(dirs, 1)->valuestring, "down") != 0))
    return bad(err, path, "\"directions\" is not [\"up\", \"down\"]");
  if (!is_list(table, R)) return bad(err, path, "\"table\" does not have a row per bin of alpha1");
  for (int a = 0; a < R; a++) {
    const cJSON *row = cJSON_GetArrayItem(table, a);
    if (!is_list(row, R))
      return bad(err, path, "a row of \"table\" does not have an entry per bin of alpha2");
    for (int b = 0; b < R; b++) {
      nbrdf_status st =
          read_entry(cJSON_GetArrayItem(row, b), split, path, a, b, m->audit_slope[a][b], err);
      if (st) return st;
    }
  }
  m->has_audit_slopes = 1;
  m->audit_slopes_both_ways = !split;
  return NBRDF_OK;
}

const double *model_audit_slopes(const nbrdf_model *m) {
  return m->has_audit_slopes ? &m->audit_slope[0][0][0][0] : NULL;
}
