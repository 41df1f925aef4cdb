/* The energy audit's slopes per bundle: the reach they give (per direction),
 * model.json's "audit_slopes" read (both forms), written and refused, the
 * measurement of `nbrdf bundle
 * audit-slopes` on a small bundle, and an audit without slopes measuring every
 * tuple (its worst then the texels' largest, read back). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_audit.h"
#include "bake/bake_audit_slopes.h"
#include "model/audit_slopes.h"
#include "model/audit_slopes_write.h"
#include "model/bundle.h"
#include "model/files.h"
#include "nbrdf/bake.h"
#include "testing.h"

enum {
  R = BAKE_AUDIT_REGIONS,
  P = NBRDF_BAKE_PARAM_COUNT,
  DIRS = BAKE_AUDIT_DIRS,
  N = R * R * P * DIRS
};
enum { UP = 0, DOWN = 1 };

static double table[N];

/* The entry of region (alpha1 bin a, alpha2 bin b). */
static double *at(double *t, int a, int b, int id, int dir) {
  return &t[(((size_t)a * R + b) * P + id) * DIRS + dir];
}

/* Reach from v to u: Σ slope · |Δu| with each parameter's largest slope over the
 * regions between, in the direction from v's value to u's. */
static void test_reach(void) {
  for (size_t k = 0; k < (size_t)N; k++)
    table[k] = 1.0;
  *at(table, 0, 0, NBRDF_BAKE_ETA, UP) = 4.0; /* region (0, 0) */
  *at(table, 1, 0, NBRDF_BAKE_ETA, UP) = 9.0; /* region (1, 0): alpha1's second bin */
  *at(table, 0, 0, NBRDF_BAKE_R0, UP) = 3.0;
  *at(table, 0, 0, NBRDF_BAKE_R0, DOWN) = 0.5;
  *at(table, 7, 7, NBRDF_BAKE_R0, DOWN) = 7.0;
  float u[P] = {0.01f, 0.5f, 0.01f, 0.5f, 0.7f, 0.5f}, v[P];
  memcpy(v, u, sizeof v);
  v[NBRDF_BAKE_ETA] = 0.4f, v[NBRDF_BAKE_R0] = 0.3f; /* both in region (0, 0), below u */
  CHECK_NEAR(bake_audit_reach(table, u, v), 4.0 * 0.1 + 3.0 * 0.2, 1e-6);
  /* the other way both fall: the down slopes */
  CHECK_NEAR(bake_audit_reach(table, v, u), 1.0 * 0.1 + 0.5 * 0.2, 1e-6);
  v[NBRDF_BAKE_ALPHA1] = 0.2f; /* now spans alpha1's bins 0 and 1: eta's up slope is 9 */
  CHECK_NEAR(bake_audit_reach(table, u, v), 1.0 * 0.19 + 9.0 * 0.1 + 3.0 * 0.2, 1e-6);
  CHECK_NEAR(bake_audit_reach(table, u, u), 0.0, 0.0);
  CHECK(isinf(bake_audit_reach(NULL, u, v)));
  double mx[P];
  bake_audit_slope_max(table, mx);
  CHECK(mx[NBRDF_BAKE_ETA] == 9.0 && mx[NBRDF_BAKE_R0] == 7.0 && mx[NBRDF_BAKE_SIGMA_T] == 1.0);
  bake_audit_slope_max(NULL, mx);
  CHECK(isinf(mx[0]));
}

/* dir/model.json's "audit_slopes" rewritten in the first form: one number an
 * entry (each pair's up slope), no "directions". */
static void to_first_form(const char *json) {
  char *text = NULL;
  size_t size = 0;
  nbrdf_error e;
  CHECK_OK(model_read_file(json, 1 << 24, &text, &size, &e), &e);
  cJSON *root = text ? cJSON_Parse(text) : NULL;
  cJSON *o = cJSON_GetObjectItemCaseSensitive(root, "audit_slopes");
  CHECK(o != NULL);
  if (!o) {
    cJSON_Delete(root), free(text);
    return;
  }
  cJSON_DeleteItemFromObjectCaseSensitive(o, "directions");
  cJSON *t = cJSON_GetObjectItemCaseSensitive(o, "table"), *row, *entry;
  cJSON_ArrayForEach(row, t) cJSON_ArrayForEach(entry, row) {
    for (int id = 0; id < P; id++) {
      double up = cJSON_GetArrayItem(cJSON_GetArrayItem(entry, id), 0)->valuedouble;
      cJSON_ReplaceItemInArray(entry, id, cJSON_CreateNumber(up));
    }
  }
  char *out = cJSON_Print(root);
  FILE *f = fopen(json, "w");
  if (f && out) fputs(out, f);
  if (f) fclose(f);
  cJSON_free(out), cJSON_Delete(root), free(text);
}

static char *slurp(const char *path) {
  char *text = NULL;
  size_t size = 0;
  nbrdf_error e;
  return model_read_file(path, 1 << 24, &text, &size, &e) == NBRDF_OK ? text : NULL;
}

/* model.json: written for the bundle's checksum only, read back exactly, refused
 * when damaged with the entry named. */
static void test_json(const char *dir) {
  nbrdf_error e, *err = &e;
  nbrdf_model *m = NULL;
  CHECK_OK(nbrdf_model_load(dir, &m, err), err);
  if (!m) return;
  CHECK(model_audit_slopes(m) == NULL); /* `bundle init` writes none */
  char json[700];
  snprintf(json, sizeof json, "%s/model.json", dir);
  char *before = slurp(json);
  CHECK_FAILS(model_audit_slopes_write(dir, "0123456789abcdef", table, NULL, err),
              NBRDF_ERR_MISMATCH, err, "checksum is not 0123456789abcdef");
  char *after = slurp(json);
  CHECK(before && after && strcmp(before, after) == 0);
  free(after);
  table[5] = NAN;
  CHECK_FAILS(model_audit_slopes_write(dir, nbrdf_model_checksum(m), table, NULL, err),
              NBRDF_ERR_ARGUMENT, err, "not a finite number");
  table[5] = 1.0;
  *at(table, 0, 0, NBRDF_BAKE_ALPHA1, DOWN) = 2.5; /* the first pair is [1, 2.5] */
  CHECK_OK(model_audit_slopes_write(dir, nbrdf_model_checksum(m), table, "a test", err), err);
  nbrdf_model *m2 = NULL;
  CHECK_OK(nbrdf_model_load(dir, &m2, err), err);
  const double *s = m2 ? model_audit_slopes(m2) : NULL;
  CHECK(s != NULL && m2->audit_slopes_both_ways == 0);
  for (size_t k = 0; s && k < (size_t)N; k++)
    CHECK_MSG(s[k] == table[k], "slope %zu: %g vs %g", k, s[k], table[k]);
  /* a model with its own decoder carries its bundle's slopes */
  nbrdf_model *derived = NULL;
  char dec[700];
  snprintf(dec, sizeof dec, "%s/decoder.safetensors", dir);
  CHECK_OK(nbrdf_model_with_decoder_file(m2, dec, &derived, err), err);
  CHECK(derived && model_audit_slopes(derived) && model_audit_slopes(derived)[3] == table[3]);
  nbrdf_model_destroy(derived);
  nbrdf_model_destroy(m2);
  /* damaged entries: the file and the entry named, the bundle refused */
  char *good = slurp(json);
  const char *edits[][2] = {
      {"\"regions\":\t8", "\"regions\":\t4"},
      {"\"parameters\":\t[\"alpha1\"", "\"parameters\":\t[\"alpha\""},
      {"\"table\":\t[[[[1, 2.5]", "\"table\":\t[[[[1, -2.5]"},
      {"\"table\":\t[[[[1, 2.5]", "\"table\":\t[[[[1, 2.5, 1]"},
      {"\"directions\":\t[\"up\", \"down\"]", "\"directions\":\t[\"down\", \"up\"]"},
      {"\"table\":\t[[[[1, 2.5]", "\"table\":\t[[[1"},
  };
  const char *needles[] = {"\"regions\" is not the audit's",
                           "\"parameters\"",
                           "table[0][0][0][1] (alpha1, down) is not a finite number > 0",
                           "[up, down] pair",
                           "\"directions\" is not",
                           "[up, down] pair"};
  for (int k = 0; good && k < 6; k++) {
    char *p = strstr(good, edits[k][0]);
    CHECK_MSG(p != NULL, "model.json has no '%s'", edits[k][0]);
    if (!p) continue;
    FILE *f = fopen(json, "w");
    fprintf(f, "%.*s%s%s", (int)(p - good), good, edits[k][1], p + strlen(edits[k][0]));
    fclose(f);
    nbrdf_model *bad = NULL;
    CHECK_FAILS(nbrdf_model_load(dir, &bad, err), NBRDF_ERR_FORMAT, err, needles[k]);
    CHECK(strstr(err->message, "model.json") != NULL);
    nbrdf_model_destroy(bad);
  }
  /* the first form (one slope both ways) is read as the same slope up and down */
  if (good) {
    FILE *f = fopen(json, "w");
    fputs(good, f);
    fclose(f);
    to_first_form(json);
    nbrdf_model *first = NULL;
    CHECK_OK(nbrdf_model_load(dir, &first, err), err);
    const double *f1 = first ? model_audit_slopes(first) : NULL;
    CHECK(f1 != NULL && first->audit_slopes_both_ways == 1); /* `bundle info` says so */
    /* both directions: the up slope */
    for (size_t k = 0; f1 && k < (size_t)N; k++)
      CHECK_MSG(f1[k] == table[k - k % DIRS], "slope %zu: %g vs %g", k, f1[k], table[k - k % DIRS]);
    nbrdf_model_destroy(first);
    /* a pair where "directions" is absent is refused */
    char *one = slurp(json), *p = one ? strstr(one, "\"table\":\t[[[1") : NULL;
    CHECK(p != NULL);
    if (p) {
      f = fopen(json, "w");
      fprintf(f, "%.*s\"table\":\t[[[[1, 1]%s", (int)(p - one), one,
              p + strlen("\"table\":\t[[[1"));
      fclose(f);
      nbrdf_model *bad = NULL;
      CHECK_FAILS(nbrdf_model_load(dir, &bad, err), NBRDF_ERR_FORMAT, err,
                  "\"directions\" is absent");
      nbrdf_model_destroy(bad);
    }
    free(one);
  }
  if (before) { /* back to no slopes */
    FILE *f = fopen(json, "w");
    fputs(before, f);
    fclose(f);
  }
  free(good), free(before);
  nbrdf_model_destroy(m);
}

static int calls;
static int count_calls(void *user, const char *stage, double done, double total) {
  (void)user;
  calls += !strcmp(stage, "audit slopes") && done <= total;
  return 0;
}
static int cancel_at_first(void *user, const char *stage, double done, double total) {
  (void)user, (void)stage, (void)total;
  return done > 0;
}

/* The measurement: every entry at least its floor 0.25, a parameter's entries in
 * a direction at least a third of its largest need that way times 1.5 and at
 * most that need times 1.5 (rounded up to 0.01), every measured step within its
 * bound both ways, deterministic, and cancellable. */
static void test_measure(const char *dir) {
  nbrdf_error e, *err = &e;
  nbrdf_model *m = NULL;
  CHECK_OK(nbrdf_model_load(dir, &m, err), err);
  if (!m) return;
  bake_audit_slopes_options o = BAKE_AUDIT_SLOPES_OPTIONS_DEFAULT;
  o.bases = 64, o.sharp_bases = 8, o.progress = count_calls;
  static double t1[N], t2[N];
  bake_audit_slopes_draws d;
  CHECK_OK(bake_audit_slopes_measure(m, &o, t1, &d, err), err);
  CHECK(calls >= 2);
  CHECK(d.n_bases == 72 && d.n_sharp == 8 && d.per == BAKE_AUDIT_SLOPES_STEPS * P + 2);
  /* each direction's largest need, from the draws: a step's rise one way is its fall the other */
  double top[P][DIRS] = {{0}};
  for (size_t b = 0; b < d.n_bases; b++)
    for (int id = 0; id < P; id++) {
      for (int j = 0; j < BAKE_AUDIT_SLOPES_STEPS; j++) {
        size_t k = b * d.per, ks = k + 1 + (size_t)id * BAKE_AUDIT_SLOPES_STEPS + (size_t)j;
        double du = d.u[ks * P + id] - d.u[k * P + id], dm = d.value[ks] - d.value[k];
        if (du == 0.0) continue;
        top[id][du > 0 ? UP : DOWN] =
            fmax(top[id][du > 0 ? UP : DOWN], (dm - BAKE_AUDIT_NOISE) / fabs(du));
        top[id][du > 0 ? DOWN : UP] =
            fmax(top[id][du > 0 ? DOWN : UP], (-dm - BAKE_AUDIT_NOISE) / fabs(du));
      }
    }
  for (int id = 0; id < P; id++)
    for (int way = 0; way < DIRS; way++) {
      double lo = INFINITY, hi = 0.0;
      for (int a = 0; a < R; a++)
        for (int b = 0; b < R; b++)
          lo = fmin(lo, *at(t1, a, b, id, way)), hi = fmax(hi, *at(t1, a, b, id, way));
      double need = top[id][way];
      CHECK_MSG(need <= d.need[id] + 1e-12, "the largest need either way is the larger of the two");
      CHECK_MSG(lo >= 0.25 && lo >= ceil(150.0 * need / 3.0) / 100.0 - 1e-9,
                "%s %s: smallest %g, need %g", nbrdf_bake_param_name((nbrdf_bake_param_id)id),
                way ? "down" : "up", lo, need);
      CHECK_MSG(hi <= fmax(0.25, ceil(150.0 * need) / 100.0) + 1e-9, "%s %s: largest %g, need %g",
                nbrdf_bake_param_name((nbrdf_bake_param_id)id), way ? "down" : "up", hi, need);
    }
  /* every stepped pair is within noise + the table's reach, rising from the base
   * to the step and from the step to the base */
  size_t misses = 0;
  for (size_t b = 0; b < d.n_bases; b++)
    for (int s = 1; s <= BAKE_AUDIT_SLOPES_STEPS * P; s++) {
      size_t k = b * d.per, ks = k + (size_t)s;
      float u[P], v[P];
      for (int id = 0; id < P; id++)
        u[id] = (float)d.u[ks * P + id], v[id] = (float)d.u[k * P + id];
      misses += d.value[ks] - d.value[k] >
                BAKE_AUDIT_NOISE + bake_audit_reach(t1, u, v) * (1.0 + 1e-6) + 1e-9;
      misses += d.value[k] - d.value[ks] >
                BAKE_AUDIT_NOISE + bake_audit_reach(t1, v, u) * (1.0 + 1e-6) + 1e-9;
    }
  CHECK_MSG(misses == 0, "%zu measured steps beyond their bound", misses);
  bake_audit_slopes_draws_free(&d);
  o.progress = NULL;
  CHECK_OK(bake_audit_slopes_measure(m, &o, t2, NULL, err), err);
  CHECK(memcmp(t1, t2, sizeof t1) == 0);
  o.progress = cancel_at_first;
  CHECK_FAILS(bake_audit_slopes_measure(m, &o, t2, NULL, err), NBRDF_ERR_CANCELLED, err,
              "cancelled");
  o.bases = 0, o.sharp_bases = 0;
  CHECK_FAILS(bake_audit_slopes_measure(m, &o, t2, NULL, err), NBRDF_ERR_ARGUMENT, err,
              "at least one");
  nbrdf_model_destroy(m);
}

/* dir/file copied to to/file. */
static void copy_file(const char *dir, const char *to, const char *file) {
  char a[700], b[700];
  snprintf(a, sizeof a, "%s/%s", dir, file);
  snprintf(b, sizeof b, "%s/%s", to, file);
  char *bytes = NULL;
  size_t size = 0;
  nbrdf_error e;
  CHECK_OK(model_read_file(a, 1 << 26, &bytes, &size, &e), &e);
  FILE *f = fopen(b, "wb");
  CHECK(f && fwrite(bytes, 1, size, f) == size);
  if (f) fclose(f);
  free(bytes);
}

/* Three tuples 0.01 apart in r0, baked with the bundle in dir: *measured of *audited. */
static void bake_three(const char *dir, size_t *measured, size_t *audited) {
  nbrdf_error e, *err = &e;
  nbrdf_model *m = NULL;
  *measured = *audited = 0;
  CHECK_OK(nbrdf_model_load(dir, &m, err), err);
  if (!m) return;
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  CHECK_OK(nbrdf_bake_param_parse("r0", "0.5,0.51,0.52", &in.param[NBRDF_BAKE_R0], err), err);
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.mip_levels = 1;
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(m, &in, &o, testing_path("audit.exr"), &rep, err), err);
  CHECK_MSG(rep.max_albedo < 0.9, "worst albedo %g (the tuples are ordinary)", rep.max_albedo);
  *measured = rep.audit_measured, *audited = rep.audited;
  nbrdf_model_destroy(m);
}

/* The shipped bundle's slopes clear tuples next to a measured one; the same bundle
 * without them has every distinct tuple measured. */
static void test_audit(void) {
  const char *src = getenv("NBRDF_SOURCE_DIR");
  if (!src) src = ".";
  char shipped[600];
  snprintf(shipped, sizeof shipped, "%s/models/default", src);
  size_t measured, audited;
  bake_three(shipped, &measured, &audited);
  CHECK_MSG(audited == 3 && measured < audited, "%zu of %zu measured", measured, audited);

  const char *to = testing_path("default-without");
  char json[700];
  snprintf(json, sizeof json, "%s/model.json", to);
  CHECK(model_make_dirs(to, NULL) == NBRDF_OK);
  for (int k = 0; k < 4; k++)
    copy_file(shipped, to, model_bundle_files[k]);
  copy_file(shipped, to, "model.json");
  char *text = slurp(json);
  cJSON *root = text ? cJSON_Parse(text) : NULL;
  CHECK(cJSON_GetObjectItemCaseSensitive(root, "audit_slopes") != NULL);
  cJSON_DeleteItemFromObjectCaseSensitive(root, "audit_slopes");
  char *out = cJSON_Print(root);
  FILE *f = fopen(json, "w");
  if (f && out) fputs(out, f);
  if (f) fclose(f);
  cJSON_free(out), cJSON_Delete(root), free(text);
  bake_three(to, &measured, &audited);
  CHECK_MSG(audited == 3 && measured == audited, "%zu of %zu measured", measured, audited);
}

int main(int argc, char **argv) {
  testing_one_blas_thread(argc, argv);
  nbrdf_error e, *err = &e;
  char dir[600];
  snprintf(dir, sizeof dir, "%s", testing_path("bundle"));
  CHECK_OK(model_bundle_init_random(dir, "slopes-test", 5, "small", err), err);
  RUN(test_reach);
  test_json(dir);
  test_measure(dir);
  RUN(test_audit);
  return testing_finish();
}
