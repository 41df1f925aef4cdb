/* model.json against the weight files: every value model.json states about
 * the networks and the tables (presets, inputs, outputs, MACs, parameters,
 * encoding, output, σT input, σ floor, every table axis node) must equal what
 * the .safetensors files hold, so that an edited model.json is refused
 * instead of describing a model that is not the one loaded. The weights'
 * checksum covers the files; this covers model.json's meaning. name,
 * trained, seed and note are statements about the model that no file can
 * confirm (a texture records the name and is refused under another). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "model/bundle_json.h"
#include "model/files.h"
#include "model/proxy.h"

typedef struct checker {
  const char *path; /* dir/model.json */
  nbrdf_error *err;
  nbrdf_status st;
} checker;

#define REBUILD_HINT                                                                               \
  "model.json was edited or a weight file replaced; if the .safetensors files are the "            \
  "intended ones, reassemble the bundle from them with `nbrdf train bundle` (docs/"                \
  "MODEL_BUNDLE.md, \"Checksums\")"

static const cJSON *member(checker *c, const cJSON *obj, const char *section, const char *key) {
  const cJSON *v = cJSON_IsObject(obj) ? cJSON_GetObjectItemCaseSensitive(obj, key) : NULL;
  if (!v && c->st == NBRDF_OK)
    c->st = core_fail(c->err, NBRDF_ERR_MISMATCH, "%s: \"%s.%s\" is missing (%s)", c->path, section,
                      key, REBUILD_HINT);
  return v;
}

static void expect_string(checker *c, const cJSON *obj, const char *section, const char *key,
                          const char *file, const char *want) {
  const cJSON *v = member(c, obj, section, key);
  if (c->st != NBRDF_OK) return;
  if (!cJSON_IsString(v) || strcmp(v->valuestring, want) != 0)
    c->st = core_fail(c->err, NBRDF_ERR_MISMATCH, "%s: \"%s.%s\" is %s, %s has \"%s\" (%s)",
                      c->path, section, key, cJSON_IsString(v) ? v->valuestring : "not a string",
                      file, want, REBUILD_HINT);
}

static void expect_number(checker *c, const cJSON *obj, const char *section, const char *key,
                          const char *file, double want) {
  const cJSON *v = member(c, obj, section, key);
  if (c->st != NBRDF_OK) return;
  if (!cJSON_IsNumber(v) || v->valuedouble != want)
    c->st = core_fail(c->err, NBRDF_ERR_MISMATCH, "%s: \"%s.%s\" is %.9g, %s has %.9g (%s)",
                       c->path, section, key, cJSON_IsNumber(v) ? v->valuedouble : NAN, file,
                       want, REBUILD_HINT);
}

/* Axis nodes are written as the shortest decimal that reads back as the
 * stored float, so the comparison is exact in float. */
static void expect_axis(checker *c, const cJSON *obj, const char *section, const char *key,
                        const float *axis, int n) {
  const cJSON *v = member(c, obj, section, key);
  if (c->st != NBRDF_OK) return;
  int count = cJSON_IsArray(v) ? cJSON_GetArraySize(v) : -1;
  if (count != n) {
    c->st = core_fail(c->err, NBRDF_ERR_MISMATCH,
                      "%s: \"%s.%s\" has %d nodes, base_tables.safetensors %d (%s)", c->path,
                      section, key, count, n, REBUILD_HINT);
    return;
  }
  for (int i = 0; i < n; i++) {
    const cJSON *x = cJSON_GetArrayItem(v, i);
    if (!cJSON_IsNumber(x) || (float)x->valuedouble != axis[i]) {
      c->st = core_fail(c->err, NBRDF_ERR_MISMATCH,
                        "%s: \"%s.%s\" node %d is %.9g, base_tables.safetensors has %.9g (%s)",
                        c->path, section, key, i, cJSON_IsNumber(x) ? x->valuedouble : NAN,
                        (double)axis[i], REBUILD_HINT);
      return;
    }
  }
}

static void expect_net(checker *c, const cJSON *root, const char *section, const char *file,
                       const char *preset, const nn_network *nn) {
  const cJSON *o = member(c, root, "model", section);
  expect_string(c, o, section, "preset", file, preset);
  expect_number(c, o, section, "inputs", file, nn_inputs(nn));
  expect_number(c, o, section, "outputs", file, nn_outputs(nn));
  expect_number(c, o, section, "macs", file, (double)nn_spec_macs(nn_get_spec(nn)));
  expect_number(c, o, section, "params", file, (double)nn_param_count(nn));
}

nbrdf_status model_bundle_check_json(const char *dir, const nbrdf_model *m, nbrdf_error *err) {
  char path[4096];
  cJSON *root = NULL;
  nbrdf_status st = model_bundle_parse_json(dir, path, &root, err);
  if (st != NBRDF_OK) return st;
  checker c = {path, err, NBRDF_OK};
  const model_decoder_config *dc = &m->decoder->cfg;
  const char *dec = "decoder.safetensors";
  expect_net(&c, root, "decoder", dec, dc->preset, m->decoder->nn);
  const cJSON *d = cJSON_GetObjectItemCaseSensitive(root, "decoder");
  expect_string(&c, d, "decoder", "encoding", dec, model_encoding_kind_name(dc->encoding.kind));
  expect_number(&c, d, "decoder", "octaves", dec, dc->encoding.octaves);
  expect_string(&c, d, "decoder", "output", dec, model_output_name(dc->output));
  expect_net(&c, root, "layering", "layering.safetensors", m->layering->preset, m->layering->nn);
  expect_string(&c, cJSON_GetObjectItemCaseSensitive(root, "layering"), "layering", "sigma_t_input",
                "layering.safetensors", "log1p");
  expect_net(&c, root, "sampler", "sampler.safetensors", m->sampler->preset, m->sampler->nn);
  expect_number(&c, cJSON_GetObjectItemCaseSensitive(root, "sampler"), "sampler", "sigma_min",
                "sampler.safetensors", MODEL_PROXY_SIGMA_MIN);
  const cJSON *tables = member(&c, root, "model", "base_tables");
  for (int k = 0; k < 2 && c.st == NBRDF_OK; k++) {
    const model_base_table *t = &m->tables[k];
    char section[64];
    snprintf(section, sizeof section, "base_tables.%s", model_table_name(t->kind));
    const cJSON *o = member(&c, tables, "base_tables", model_table_name(t->kind));
    for (int a = 0; a < 2; a++)
      expect_axis(&c, o, section, model_table_param(t->kind, a), t->axis[a], t->n[a]);
  }
  cJSON_Delete(root);
  return c.st;
}
