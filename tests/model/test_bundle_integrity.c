/* The bundle's integrity checks (issue 15, item 8): model.json must record
 * the weights' checksum, a flipped weight byte is refused with or without
 * it, and model.json's statements about the networks and the tables (grids,
 * architecture) must match the weight files; descriptive fields (note) may
 * be edited. The shipped bundles keep the checksums their textures record. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/bundle.h"
#include "model/files.h"
#include "testing.h"

static char *path_in(const char *dir, const char *file) {
  static char buf[8][8192];
  static int next;
  char *p = buf[next++ % 8];
  snprintf(p, sizeof buf[0], "%.4000s/%.1000s", dir, file);
  return p;
}

static char *saved_json; /* the bundle's original model.json */
static char bundle_dir[4096];

static cJSON *read_json(const char *dir) {
  char *text = NULL;
  size_t size = 0;
  if (model_read_file(path_in(dir, "model.json"), UINT64_MAX, &text, &size, NULL) != NBRDF_OK)
    return NULL;
  cJSON *root = cJSON_Parse(text);
  free(text);
  return root;
}

static void write_json(const char *dir, cJSON *root) {
  char *text = cJSON_Print(root);
  nbrdf_error err = {0};
  CHECK_OK(model_write_text_file(dir, "model.json", text, &err), &err);
  cJSON_free(text);
  cJSON_Delete(root);
}

static void restore_json(const char *dir) {
  nbrdf_error err = {0};
  CHECK_OK(model_write_text_file(dir, "model.json", saved_json, &err), &err);
}

static void flip_byte(const char *path, long from_end) {
  FILE *f = fopen(path, "r+b");
  if (!f) {
    CHECK_MSG(0, "cannot open %s", path);
    return;
  }
  fseek(f, -from_end, SEEK_END);
  int c = fgetc(f);
  fseek(f, -from_end, SEEK_END);
  fputc(c ^ 0x01, f);
  fclose(f);
}

/* Loading `dir` fails with `status` and a message holding `needle`. */
static void refused(const char *dir, nbrdf_status status, const char *needle) {
  nbrdf_error err = {0};
  nbrdf_model *m = NULL;
  CHECK_FAILS(nbrdf_model_load(dir, &m, &err), status, &err, needle);
  CHECK(m == NULL);
  nbrdf_model_destroy(m);
}

static void loads(const char *dir) {
  nbrdf_error err = {0};
  nbrdf_model *m = NULL;
  CHECK_OK(nbrdf_model_load(dir, &m, &err), &err);
  nbrdf_model_destroy(m);
}

static void test_checksum_required(void) {
  const char *dir = bundle_dir;
  cJSON *root = read_json(dir);
  cJSON_DeleteItemFromObjectCaseSensitive(root, "checksum");
  write_json(dir, root);
  refused(dir, NBRDF_ERR_FORMAT, "model.json: no \"checksum\"");
  refused(dir, NBRDF_ERR_FORMAT, "nbrdf train bundle");
  /* Without a checksum a flipped weight byte used to load: now refused. */
  char *bytes = NULL;
  size_t size = 0;
  nbrdf_error err = {0};
  CHECK_OK(model_read_file(path_in(dir, "decoder.safetensors"), UINT64_MAX, &bytes, &size, &err),
           &err);
  flip_byte(path_in(dir, "decoder.safetensors"), 5);
  refused(dir, NBRDF_ERR_FORMAT, "checksum");
  /* With the checksum, the same flip is refused as a mismatch. */
  restore_json(dir);
  refused(dir, NBRDF_ERR_MISMATCH, "model.json: checksum");
  flip_byte(path_in(dir, "decoder.safetensors"), 5);
  loads(dir);
  /* A byte of each other weight file. */
  for (int i = 1; i < 4; i++) {
    flip_byte(path_in(dir, model_bundle_files[i]), 3);
    refused(dir, NBRDF_ERR_MISMATCH, "does not match the weight files");
    flip_byte(path_in(dir, model_bundle_files[i]), 3);
  }
  loads(dir);
  free(bytes);
}

/* Sets section.key (section NULL: the root) to a number or a string. */
static void edit(const char *dir, const char *section, const char *key, const char *text,
                 double number) {
  cJSON *root = read_json(dir);
  cJSON *obj = section ? cJSON_GetObjectItemCaseSensitive(root, section) : root;
  cJSON *v = text ? cJSON_CreateString(text) : cJSON_CreateNumber(number);
  if (!obj || !cJSON_ReplaceItemInObjectCaseSensitive(obj, key, v)) {
    CHECK_MSG(0, "model.json has no %s.%s", section ? section : "", key);
    cJSON_Delete(v);
  }
  write_json(dir, root);
}

static void test_architecture_edits(void) {
  const char *dir = bundle_dir;
  static const struct {
    const char *section, *key, *text;
    double number;
    const char *needle;
  } edits[] = {
      {"decoder", "encoding", "cartesian", 0, "\"decoder.encoding\" is cartesian"},
      {"decoder", "output", "f", 0, "\"decoder.output\""},
      {"decoder", "octaves", NULL, 4, "\"decoder.octaves\" is 4"},
      {"decoder", "preset", "paper", 0, "\"decoder.preset\""},
      {"decoder", "macs", NULL, 1058560, "\"decoder.macs\""},
      {"decoder", "inputs", NULL, 39, "\"decoder.inputs\""},
      {"layering", "preset", "small", 0, "\"layering.preset\""},
      {"layering", "params", NULL, 1, "\"layering.params\""},
      {"layering", "sigma_t_input", "linear", 0, "\"layering.sigma_t_input\""},
      {"sampler", "outputs", NULL, 3, "\"sampler.outputs\""},
      {"sampler", "sigma_min", NULL, 0.01, "\"sampler.sigma_min\""},
  };
  for (size_t i = 0; i < sizeof edits / sizeof edits[0]; i++) {
    edit(dir, edits[i].section, edits[i].key, edits[i].text, edits[i].number);
    refused(dir, NBRDF_ERR_MISMATCH, edits[i].needle);
    restore_json(dir);
  }
  /* A whole section removed. */
  cJSON *root = read_json(dir);
  cJSON_DeleteItemFromObjectCaseSensitive(root, "layering");
  write_json(dir, root);
  refused(dir, NBRDF_ERR_MISMATCH, "\"model.layering\" is missing");
  restore_json(dir);
  /* Descriptive fields may be edited. */
  edit(dir, NULL, "note", "retouched by hand", 0);
  loads(dir);
  restore_json(dir);
}

static void test_grid_edits(void) {
  const char *dir = bundle_dir;
  /* One node moved, one node dropped, one node added: each refused. */
  for (int what = 0; what < 3; what++) {
    cJSON *root = read_json(dir);
    cJSON *eta = cJSON_GetObjectItemCaseSensitive(
        cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(root, "base_tables"),
                                         "dielectric"),
        "eta");
    CHECK(cJSON_GetArraySize(eta) > 3);
    if (what == 0) cJSON_ReplaceItemInArray(eta, 2, cJSON_CreateNumber(1.3));
    if (what == 1) cJSON_DeleteItemFromArray(eta, 1);
    if (what == 2) cJSON_AddItemToArray(eta, cJSON_CreateNumber(2.5));
    write_json(dir, root);
    refused(dir, NBRDF_ERR_MISMATCH,
            what == 0 ? "\"base_tables.dielectric.eta\" node 2 is 1.3"
                      : "base_tables.dielectric.eta");
    restore_json(dir);
  }
  cJSON *root = read_json(dir);
  cJSON *r0 = cJSON_GetObjectItemCaseSensitive(
      cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(root, "base_tables"),
                                       "conductor"),
      "r0");
  cJSON_ReplaceItemInArray(r0, 0, cJSON_CreateNumber(0.001));
  write_json(dir, root);
  refused(dir, NBRDF_ERR_MISMATCH, "\"base_tables.conductor.r0\" node 0");
  restore_json(dir);
  loads(dir);
}

/* The shipped bundles pass every check and keep the checksums recorded in
 * the textures baked with them (docs/MODEL_CARD_DEFAULT.md): models/default,
 * models/medium (its decoder half the cost), models/v1, the default until
 * 2026-11-26, kept for its textures, and models/tails (default's layering network
 * fine-tuned for the tails; docs/MODEL_CARD_TAILS.md). */
static void test_shipped_bundles(void) {
  static const char *const dirs[4][2] = {{"models/default", "e3f05d7c80d59511"},
                                         {"models/medium", "4ba239f7ac35f1d8"},
                                         {"models/v1", "0ab22d273b6be904"},
                                         {"models/tails", "331b5980d9948d2d"}};
  const char *src = testing_source_dir();
  for (int k = 0; k < 4; k++) {
    nbrdf_error err = {0};
    nbrdf_model *m = NULL;
    CHECK_OK(nbrdf_model_load(path_in(src, dirs[k][0]), &m, &err), &err);
    if (m)
      CHECK_MSG(!strcmp(nbrdf_model_checksum(m), dirs[k][1]), "%s: checksum %s, expected %s",
                dirs[k][0], nbrdf_model_checksum(m), dirs[k][1]);
    nbrdf_model_destroy(m);
  }
}

int main(void) {
  char *dir = bundle_dir;
  snprintf(dir, sizeof bundle_dir, "%s/integrity", testing_tmpdir());
  nbrdf_error err = {0};
  size_t size = 0;
  CHECK_OK(model_bundle_init_random(dir, "integrity", 4, "small", &err), &err);
  CHECK_OK(model_read_file(path_in(dir, "model.json"), UINT64_MAX, &saved_json, &size, &err), &err);
  if (!saved_json) return testing_finish();
  loads(dir);
  RUN(test_checksum_required);
  RUN(test_architecture_edits);
  RUN(test_grid_edits);
  RUN(test_shipped_bundles);
  free(saved_json);
  return testing_finish();
}
