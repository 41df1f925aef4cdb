/* JSON form of a network spec, carried in the safetensors __metadata__ next to the weights. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "nn/nn.h"

#define SPEC_FORMAT "nbrdf-nn"
#define SPEC_VERSION 1

nbrdf_status nn_spec_to_json(const nn_spec *spec, char **json, nbrdf_error *err) {
  *json = NULL;
  nbrdf_status st = nn_spec_validate(spec, err);
  if (st != NBRDF_OK) return st;
  cJSON *root = cJSON_CreateObject();
  cJSON *layers = NULL;
  int ok = root && cJSON_AddStringToObject(root, "format", SPEC_FORMAT) &&
           cJSON_AddNumberToObject(root, "version", SPEC_VERSION) &&
           cJSON_AddNumberToObject(root, "inputs", spec->n_inputs) &&
           (layers = cJSON_AddArrayToObject(root, "layers"));
  for (int i = 0; ok && i < spec->n_layers; i++) {
    const nn_layer_spec *l = &spec->layers[i];
    cJSON *o = cJSON_CreateObject();
    ok = o && cJSON_AddItemToArray(layers, o) &&
         cJSON_AddStringToObject(o, "kind", nn_kind_name(l->kind));
    if (ok && (l->kind == NBRDF_NN_LINEAR || l->kind == NBRDF_NN_PLAIN))
      ok = cJSON_AddNumberToObject(o, "width", l->width) != NULL;
    if (ok && l->kind == NBRDF_NN_RESIDUAL && l->hidden > 0)
      ok = cJSON_AddNumberToObject(o, "hidden", l->hidden) != NULL;
    if (ok && l->has_skip) ok = cJSON_AddNumberToObject(o, "skip", l->skip_from) != NULL;
  }
  char *text = ok ? cJSON_PrintUnformatted(root) : NULL;
  cJSON_Delete(root);
  if (!text) return core_fail(err, NBRDF_ERR_MEMORY, "network spec: out of memory writing JSON");
  /* cJSON's allocator is malloc by default; copy anyway so callers can always use free(). */
  *json = malloc(strlen(text) + 1);
  if (*json) strcpy(*json, text);
  cJSON_free(text);
  if (!*json) return core_fail(err, NBRDF_ERR_MEMORY, "network spec: out of memory");
  return NBRDF_OK;
}

/* A JSON number that is an integer in [lo, hi]. */
static nbrdf_status get_int(const cJSON *item, const char *where, const char *key, int lo, int hi,
                            int *out, nbrdf_error *err) {
  if (!cJSON_IsNumber(item))
    return core_fail(err, NBRDF_ERR_FORMAT, "network spec: %s\"%s\" must be a number", where, key);
  double v = item->valuedouble;
  if (!(v >= lo && v <= hi) || v != floor(v))
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "network spec: %s\"%s\" = %g, expected an integer in %d..%d", where, key, v,
                     lo, hi);
  *out = (int)v;
  return NBRDF_OK;
}

static nbrdf_status parse_layer(const cJSON *o, int i, nn_layer_spec *l, nbrdf_error *err) {
  char where[32];
  snprintf(where, sizeof where, "layer %d: ", i);
  if (!cJSON_IsObject(o))
    return core_fail(err, NBRDF_ERR_FORMAT, "network spec: %sexpected an object", where);
  memset(l, 0, sizeof *l);
  const cJSON *kind = cJSON_GetObjectItemCaseSensitive(o, "kind");
  if (!cJSON_IsString(kind))
    return core_fail(err, NBRDF_ERR_FORMAT, "network spec: %s\"kind\" missing or not a string",
                     where);
  for (int k = NBRDF_NN_LINEAR; k <= NBRDF_NN_RESIDUAL; k++)
    if (strcmp(kind->valuestring, nn_kind_name((nn_kind)k)) == 0) l->kind = (nn_kind)k;
  if (!l->kind)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "network spec: %sunknown kind \"%s\" (linear, layernorm, relu, plain, "
                     "residual)",
                     where, kind->valuestring);
  nbrdf_status st = NBRDF_OK;
  for (const cJSON *it = o->child; it && st == NBRDF_OK; it = it->next) {
    if (strcmp(it->string, "kind") == 0) continue;
    if (strcmp(it->string, "width") == 0) {
      st = get_int(it, where, "width", 1, NBRDF_NN_MAX_WIDTH, &l->width, err);
    } else if (strcmp(it->string, "hidden") == 0) {
      st = get_int(it, where, "hidden", 1, NBRDF_NN_MAX_WIDTH, &l->hidden, err);
    } else if (strcmp(it->string, "skip") == 0) {
      st = get_int(it, where, "skip", 0, NBRDF_NN_MAX_LAYERS, &l->skip_from, err);
      l->has_skip = 1;
    } else {
      st =
          core_fail(err, NBRDF_ERR_FORMAT, "network spec: %sunknown key \"%s\"", where, it->string);
    }
  }
  return st;
}

nbrdf_status nn_spec_from_json(const char *json, nn_spec *spec, nbrdf_error *err) {
  if (!json) return core_fail(err, NBRDF_ERR_ARGUMENT, "network spec: JSON text is NULL");
  cJSON *root = cJSON_Parse(json);
  if (!root) {
    const char *at = cJSON_GetErrorPtr();
    return core_fail(err, NBRDF_ERR_FORMAT, "network spec: invalid JSON near offset %ld",
                     at ? (long)(at - json) : -1L);
  }
  nn_spec s;
  nn_spec_init(&s, 0);
  nbrdf_status st = NBRDF_OK;
  const cJSON *format = cJSON_GetObjectItemCaseSensitive(root, "format");
  const cJSON *version = cJSON_GetObjectItemCaseSensitive(root, "version");
  const cJSON *inputs = cJSON_GetObjectItemCaseSensitive(root, "inputs");
  const cJSON *layers = cJSON_GetObjectItemCaseSensitive(root, "layers");
  int v = 0;
  if (!cJSON_IsObject(root)) {
    st = core_fail(err, NBRDF_ERR_FORMAT, "network spec: expected a JSON object");
  } else if (!cJSON_IsString(format) || strcmp(format->valuestring, SPEC_FORMAT) != 0) {
    st = core_fail(err, NBRDF_ERR_FORMAT, "network spec: \"format\" must be \"%s\"", SPEC_FORMAT);
  } else if ((st = get_int(version, "", "version", 1, 1000000, &v, err)) != NBRDF_OK) {
  } else if (v != SPEC_VERSION) {
    st = core_fail(err, NBRDF_ERR_FORMAT,
                   "network spec: version %d is not supported (this build reads %d)", v,
                   SPEC_VERSION);
  } else if ((st = get_int(inputs, "", "inputs", 1, NBRDF_NN_MAX_WIDTH, &s.n_inputs, err)) !=
             NBRDF_OK) {
  } else if (!cJSON_IsArray(layers)) {
    st = core_fail(err, NBRDF_ERR_FORMAT, "network spec: \"layers\" missing or not an array");
  } else if (cJSON_GetArraySize(layers) > NBRDF_NN_MAX_LAYERS) {
    st = core_fail(err, NBRDF_ERR_FORMAT, "network spec: %d layers, at most %d supported",
                   cJSON_GetArraySize(layers), NBRDF_NN_MAX_LAYERS);
  }
  for (const cJSON *it = root->child; st == NBRDF_OK && it; it = it->next) {
    if (strcmp(it->string, "format") && strcmp(it->string, "version") &&
        strcmp(it->string, "inputs") && strcmp(it->string, "layers"))
      st = core_fail(err, NBRDF_ERR_FORMAT, "network spec: unknown key \"%s\"", it->string);
  }
  if (st == NBRDF_OK) {
    const cJSON *o;
    cJSON_ArrayForEach(o, layers) {
      st = parse_layer(o, s.n_layers, &s.layers[s.n_layers], err);
      if (st != NBRDF_OK) break;
      s.n_layers++;
    }
  }
  cJSON_Delete(root);
  if (st != NBRDF_OK) return st;
  st = nn_spec_validate(&s, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "network spec: ");
    if (err) err->status = NBRDF_ERR_FORMAT;
    return NBRDF_ERR_FORMAT;
  }
  *spec = s;
  return NBRDF_OK;
}
