/* Writes model.json's "audit_slopes" (audit_slopes_write.h). */
#include "model/audit_slopes_write.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "model/audit_slopes.h"
#include "model/bundle_json.h"
#include "model/files.h"

enum { R = MODEL_AUDIT_REGIONS, P = MODEL_AUDIT_PARAMS, DIRS = MODEL_AUDIT_DIRS };

static cJSON *slopes_json(const double *table, const char *note) {
  cJSON *o = cJSON_CreateObject(), *names = cJSON_CreateArray(), *t = cJSON_CreateArray();
  const char *const dir_names[DIRS] = {"up", "down"};
  cJSON *dirs = cJSON_CreateStringArray(dir_names, DIRS);
  if (!o || !names || !t || !dirs) {
    cJSON_Delete(o), cJSON_Delete(names), cJSON_Delete(t), cJSON_Delete(dirs);
    return NULL;
  }
  cJSON_AddNumberToObject(o, "regions", R);
  for (int id = 0; id < P; id++)
    cJSON_AddItemToArray(names, cJSON_CreateString(model_audit_slopes_params[id]));
  cJSON_AddItemToObject(o, "parameters", names);
  cJSON_AddItemToObject(o, "directions", dirs);
  if (note) cJSON_AddStringToObject(o, "note", note);
  for (int a = 0; a < R; a++) {
    cJSON *row = cJSON_CreateArray();
    for (int b = 0; b < R; b++) {
      cJSON *e = cJSON_CreateArray();
      for (int id = 0; id < P; id++)
        cJSON_AddItemToArray(e, cJSON_CreateDoubleArray(
                                    table + (((size_t)a * R + b) * P + (size_t)id) * DIRS, DIRS));
      cJSON_AddItemToArray(row, e);
    }
    cJSON_AddItemToArray(t, row);
  }
  cJSON_AddItemToObject(o, "table", t);
  return o;
}

nbrdf_status model_audit_slopes_write(const char *dir, const char *checksum, const double *table,
                                      const char *note, nbrdf_error *err) {
  for (size_t k = 0; k < (size_t)R * R * P * DIRS; k++)
    if (!isfinite(table[k]) || !(table[k] > 0.0))
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "%s: audit slope %zu is %g, not a finite number > 0 (nothing written)", dir,
                       k, table[k]);
  char path[4096];
  cJSON *root = NULL;
  nbrdf_status st = model_bundle_parse_json(dir, path, &root, err);
  if (st != NBRDF_OK) return st;
  const cJSON *sum = cJSON_GetObjectItemCaseSensitive(root, "checksum");
  if (!cJSON_IsString(sum) || strcmp(sum->valuestring, checksum) != 0) {
    st = core_fail(err, NBRDF_ERR_MISMATCH,
                   "%s: its checksum is not %s, the weights the slopes were measured with "
                   "(the bundle changed while they were measured?); nothing written",
                   path, checksum);
    cJSON_Delete(root);
    return st;
  }
  cJSON *o = slopes_json(table, note);
  char *text = NULL;
  if (o) {
    cJSON_DeleteItemFromObjectCaseSensitive(root, "audit_slopes");
    cJSON_AddItemToObject(root, "audit_slopes", o);
    text = cJSON_Print(root);
  }
  if (!text)
    st = core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  else
    st = model_write_text_file(dir, "model.json", text, err);
  cJSON_free(text);
  cJSON_Delete(root);
  return st;
}
