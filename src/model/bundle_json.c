#include "model/bundle_json.h"

#include <cjson/cJSON.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "model/audit_slopes.h"
#include "model/files.h"
#include "model/proxy.h"

nbrdf_status model_bundle_parse_json(const char *dir, char path[4096], cJSON **root,
                                     nbrdf_error *err) {
  *root = NULL;
  int n = snprintf(path, 4096, "%s/model.json", dir);
  if (n < 0 || n >= 4096) return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: path too long", dir);
  char *text = NULL;
  size_t size = 0;
  nbrdf_status st = model_read_file(path, MODEL_JSON_MAX, &text, &size, err);
  if (st != NBRDF_OK) return st;
  *root = cJSON_ParseWithLength(text, size);
  free(text);
  if (!cJSON_IsObject(*root)) {
    cJSON_Delete(*root);
    *root = NULL;
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: not a JSON object", path);
  }
  return NBRDF_OK;
}

static int is_checksum_hex(const char *s) {
  return strlen(s) == 16 && strspn(s, "0123456789abcdef") == 16;
}

/* The optional "reads_textures_of" list into m->reads. */
static nbrdf_status read_reads(const cJSON *root, const char *path, nbrdf_model *m,
                               nbrdf_error *err) {
  const cJSON *list = cJSON_GetObjectItemCaseSensitive(root, "reads_textures_of");
  m->n_reads = 0;
  if (!list) return NBRDF_OK;
  if (!cJSON_IsArray(list) || cJSON_GetArraySize(list) > MODEL_READS_MAX)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: \"reads_textures_of\" must be a list of at most %d {\"name\", "
                     "\"checksum\"} objects",
                     path, MODEL_READS_MAX);
  const cJSON *e;
  cJSON_ArrayForEach(e, list) {
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(e, "name");
    const cJSON *sum = cJSON_GetObjectItemCaseSensitive(e, "checksum");
    model_bundle_ref *r = &m->reads[m->n_reads];
    if (!cJSON_IsString(name) || !name->valuestring[0] ||
        strlen(name->valuestring) >= sizeof r->name || !cJSON_IsString(sum) ||
        !is_checksum_hex(sum->valuestring))
      return core_fail(err, NBRDF_ERR_FORMAT,
                       "%s: \"reads_textures_of\" entry %d needs a \"name\" of 1..%zu "
                       "characters and a \"checksum\" of 16 lower-case hex digits",
                       path, m->n_reads + 1, sizeof r->name - 1);
    snprintf(r->name, sizeof r->name, "%s", name->valuestring);
    snprintf(r->checksum_hex, sizeof r->checksum_hex, "%s", sum->valuestring);
    m->n_reads++;
  }
  return NBRDF_OK;
}

nbrdf_status model_bundle_read_json(const char *dir, nbrdf_model *m, char checksum[17],
                                    nbrdf_error *err) {
  char path[4096];
  cJSON *root = NULL;
  nbrdf_status st = model_bundle_parse_json(dir, path, &root, err);
  if (st != NBRDF_OK) return st;
  const cJSON *format = cJSON_GetObjectItemCaseSensitive(root, "format");
  const cJSON *version = cJSON_GetObjectItemCaseSensitive(root, "version");
  const cJSON *name = cJSON_GetObjectItemCaseSensitive(root, "name");
  const cJSON *trained = cJSON_GetObjectItemCaseSensitive(root, "trained");
  const cJSON *dim = cJSON_GetObjectItemCaseSensitive(root, "latent_dim");
  const cJSON *sum = cJSON_GetObjectItemCaseSensitive(root, "checksum");
  if (!cJSON_IsString(format) || strcmp(format->valuestring, MODEL_BUNDLE_FORMAT) != 0)
    st =
        core_fail(err, NBRDF_ERR_FORMAT, "%s: \"format\" is not \"%s\"", path, MODEL_BUNDLE_FORMAT);
  else if (!cJSON_IsNumber(version) || version->valuedouble != MODEL_BUNDLE_VERSION)
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: \"version\" is not %d (a newer nbrdf wrote it?)",
                   path, MODEL_BUNDLE_VERSION);
  else if (!cJSON_IsString(name) || !name->valuestring[0] ||
           strlen(name->valuestring) >= sizeof m->name)
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: \"name\" must be a string of 1..%zu characters",
                   path, sizeof m->name - 1);
  else if (!cJSON_IsBool(trained))
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: \"trained\" must be true or false", path);
  else if (!cJSON_IsNumber(dim) || dim->valuedouble != floor(dim->valuedouble) ||
           dim->valuedouble < 1 || dim->valuedouble > 4096)
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: \"latent_dim\" must be an integer in 1..4096", path);
  else if (!sum)
    st = core_fail(err, NBRDF_ERR_FORMAT,
                   "%s: no \"checksum\" (a bundle records the checksum of its four .safetensors "
                   "files, so that a damaged or replaced file is refused); if the files are the "
                   "intended ones, reassemble the bundle from them with `nbrdf train bundle -o "
                   "NEW_DIR --name NAME --decoder F --tables F --layering F --sampler F "
                   "[--card F] [--note TEXT]`, which writes model.json with it "
                   "(docs/MODEL_BUNDLE.md, \"Checksums\")",
                   path);
  else if (!cJSON_IsString(sum) || !is_checksum_hex(sum->valuestring))
    st =
        core_fail(err, NBRDF_ERR_FORMAT, "%s: \"checksum\" must be 16 lower-case hex digits", path);
  if (st == NBRDF_OK) st = read_reads(root, path, m, err);
  if (st == NBRDF_OK) st = model_audit_slopes_read(root, path, m, err);
  if (st == NBRDF_OK) {
    snprintf(m->name, sizeof m->name, "%s", name->valuestring);
    m->trained = cJSON_IsTrue(trained);
    m->latent_dim = (int)dim->valuedouble;
    snprintf(checksum, 17, "%s", sum->valuestring);
  }
  cJSON_Delete(root);
  return st;
}

/* The shortest decimal that reads back as the same float, as a double, so that
 * model.json shows 0.05 rather than 0.050000000745058060. */
static double short_decimal(float x) {
  char buf[32];
  for (int digits = 1; digits <= 9; digits++) {
    snprintf(buf, sizeof buf, "%.*g", digits, (double)x);
    double d = strtod(buf, NULL);
    if ((float)d == x) return d;
  }
  return x;
}

static cJSON *axis_json(const float *axis, int n) {
  cJSON *a = cJSON_CreateArray();
  for (int i = 0; a && i < n; i++)
    cJSON_AddItemToArray(a, cJSON_CreateNumber(short_decimal(axis[i])));
  return a;
}

static cJSON *net_json(const char *preset, const nn_network *nn) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "preset", preset);
  cJSON_AddNumberToObject(o, "inputs", nn_inputs(nn));
  cJSON_AddNumberToObject(o, "outputs", nn_outputs(nn));
  cJSON_AddNumberToObject(o, "macs", (double)nn_spec_macs(nn_get_spec(nn)));
  cJSON_AddNumberToObject(o, "params", (double)nn_param_count(nn));
  return o;
}

nbrdf_status model_bundle_write_json(const char *dir, const model_bundle_parts *p,
                                     uint64_t checksum, nbrdf_error *err) {
  char hex[17];
  snprintf(hex, sizeof hex, "%016" PRIx64, checksum);
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "format", MODEL_BUNDLE_FORMAT);
  cJSON_AddNumberToObject(root, "version", MODEL_BUNDLE_VERSION);
  cJSON_AddStringToObject(root, "name", p->name);
  cJSON_AddBoolToObject(root, "trained", p->trained);
  cJSON_AddNumberToObject(root, "latent_dim", p->decoder->cfg.latent_dim);
  cJSON_AddNumberToObject(root, "seed", (double)p->seed);
  cJSON_AddStringToObject(root, "checksum", hex);
  cJSON *dec = net_json(p->decoder->cfg.preset, p->decoder->nn);
  cJSON_AddStringToObject(dec, "encoding", model_encoding_kind_name(p->decoder->cfg.encoding.kind));
  cJSON_AddNumberToObject(dec, "octaves", p->decoder->cfg.encoding.octaves);
  cJSON_AddStringToObject(dec, "output", model_output_name(p->decoder->cfg.output));
  cJSON_AddItemToObject(root, "decoder", dec);
  cJSON *lay = net_json(p->layering->preset, p->layering->nn);
  cJSON_AddStringToObject(lay, "sigma_t_input", "log1p");
  cJSON_AddItemToObject(root, "layering", lay);
  cJSON *smp = net_json(p->sampler->preset, p->sampler->nn);
  cJSON_AddNumberToObject(smp, "sigma_min", MODEL_PROXY_SIGMA_MIN);
  cJSON_AddItemToObject(root, "sampler", smp);
  cJSON *tables = cJSON_CreateObject();
  for (int k = 0; k < 2; k++) {
    const model_base_table *t = p->tables[k];
    cJSON *o = cJSON_CreateObject();
    for (int a = 0; a < 2; a++)
      cJSON_AddItemToObject(o, model_table_param(t->kind, a), axis_json(t->axis[a], t->n[a]));
    cJSON_AddItemToObject(tables, model_table_name(t->kind), o);
  }
  cJSON_AddItemToObject(root, "base_tables", tables);
  if (p->note) cJSON_AddStringToObject(root, "note", p->note);
  if (p->n_reads > 0) {
    cJSON *list = cJSON_AddArrayToObject(root, "reads_textures_of");
    for (int k = 0; list && k < p->n_reads; k++) {
      cJSON *o = cJSON_CreateObject();
      cJSON_AddStringToObject(o, "name", p->reads[k].name);
      cJSON_AddStringToObject(o, "checksum", p->reads[k].checksum_hex);
      cJSON_AddItemToArray(list, o);
    }
  }
  char *text = cJSON_Print(root);
  cJSON_Delete(root);
  if (!text) return core_fail(err, NBRDF_ERR_MEMORY, "%s/model.json: out of memory", dir);
  size_t len = strlen(text);
  char *line = malloc(len + 2);
  nbrdf_status st;
  if (!line) {
    st = core_fail(err, NBRDF_ERR_MEMORY, "%s/model.json: out of memory", dir);
  } else {
    memcpy(line, text, len);
    memcpy(line + len, "\n", 2);
    st = model_write_text_file(dir, "model.json", line, err);
  }
  free(line);
  cJSON_free(text);
  return st;
}

/* Appends to a growing card; the card is short, a fixed buffer is plenty. */
typedef struct card {
  char text[16384];
  size_t len;
} card;

static void add(card *c, const char *fmt, ...) NBRDF_PRINTF(2, 3);
static void add(card *c, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(c->text + c->len, sizeof c->text - c->len, fmt, ap);
  va_end(ap);
  if (n > 0)
    c->len += (size_t)n < sizeof c->text - c->len ? (size_t)n : sizeof c->text - 1 - c->len;
}

static void add_net(card *c, const char *what, const char *preset, const nn_network *nn) {
  add(c, "| %s | %s | %d -> %d | %" PRId64 " | %zu |\n", what, preset, nn_inputs(nn),
      nn_outputs(nn), nn_spec_macs(nn_get_spec(nn)), nn_param_count(nn));
}

nbrdf_status model_bundle_write_card(const char *dir, const model_bundle_parts *p,
                                     uint64_t checksum, nbrdf_error *err) {
  if (p->card) return model_write_text_file(dir, "MODEL_CARD.md", p->card, err);
  card *c = calloc(1, sizeof *c);
  if (!c) return core_fail(err, NBRDF_ERR_MEMORY, "%s/MODEL_CARD.md: out of memory", dir);
  add(c, "# Model card: %s\n\n", p->name);
  if (!p->trained)
    add(c,
        "**UNTRAINED.** Every network holds random initial weights (seed %" PRIu64
        ") and the base tables hold smooth random latents. Its BRDF values mean nothing: "
        "this bundle exists so that the bake, the evaluator, the Blender add-on and the "
        "shaders can be built and tested before training finishes.\n\n",
        p->seed);
  add(c, "- checksum (FNV-1a 64 over the four .safetensors files): `%016" PRIx64 "`\n", checksum);
  add(c, "- latent dimension: %d floats per colour channel\n", p->decoder->cfg.latent_dim);
  add(c, "- decoder: %s encoding, %d octaves, output %s\n",
      model_encoding_kind_name(p->decoder->cfg.encoding.kind), p->decoder->cfg.encoding.octaves,
      model_output_name(p->decoder->cfg.output));
  if (p->note) add(c, "- note: %s\n", p->note);
  add(c, "\n## Architecture\n\n| network | preset | inputs -> outputs | MACs per query | "
         "parameters |\n"
         "|---|---|---|---|---|\n");
  add_net(c, "decoder", p->decoder->cfg.preset, p->decoder->nn);
  add_net(c, "layering", p->layering->preset, p->layering->nn);
  add_net(c, "sampler", p->sampler->preset, p->sampler->nn);
  add(c, "\n## Base latent tables\n\n");
  for (int k = 0; k < 2; k++) {
    const model_base_table *t = p->tables[k];
    add(c, "- %s: %d x %d grid of (%s in [%g, %g], %s in [%g, %g])\n", model_table_name(t->kind),
        t->n[0], t->n[1], model_table_param(t->kind, 0), t->axis[0][0], t->axis[0][t->n[0] - 1],
        model_table_param(t->kind, 1), t->axis[1][0], t->axis[1][t->n[1] - 1]);
  }
  add(c, "\n## Measured accuracy and cost\n\n%s\n",
      p->trained ? "See the training report that produced this bundle."
                 : "None: an untrained bundle has no accuracy to report.");
  nbrdf_status st = model_write_text_file(dir, "MODEL_CARD.md", c->text, err);
  free(c);
  return st;
}
