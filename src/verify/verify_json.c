/* The verify report as JSON for pipelines (fields: docs/VERIFY.md). Lobe
 * errors are in percent, as docs/METRICS.md reports them; a damaged texel's
 * infinite error is written as null (JSON has no infinity). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/output_file.h"
#include "model/material.h"
#include "verify/verify_internal.h"
#include "verify/verify_write.h"

static void number(cJSON *o, const char *key, double v) {
  if (isfinite(v))
    cJSON_AddNumberToObject(o, key, v);
  else
    cJSON_AddNullToObject(o, key);
}

static cJSON *summary(const nbrdf_verify_summary *s) {
  cJSON *o = cJSON_CreateObject();
  if (s->level >= 0) cJSON_AddNumberToObject(o, "level", s->level);
  cJSON_AddNumberToObject(o, "texels", (double)s->texels);
  number(o, "lobe_error_median_pct", 100 * s->median);
  number(o, "lobe_error_p90_pct", 100 * s->p90);
  number(o, "lobe_error_worst_pct", 100 * s->worst);
  number(o, "albedo_error_median", s->albedo_median);
  number(o, "reference_noise_median_pct", 100 * s->noise_median);
  return o;
}

static cJSON *texel(const nbrdf_verify_texel *t, int colours) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "level", t->level);
  cJSON_AddNumberToObject(o, "x", t->x);
  cJSON_AddNumberToObject(o, "y", t->y);
  cJSON_AddNumberToObject(o, "footprint", t->footprint);
  number(o, "lobe_error_pct", 100 * t->lobe_error);
  number(o, "albedo_error", t->albedo_error);
  number(o, "reference_noise_pct", 100 * t->reference_noise);
  number(o, "max_albedo", t->max_albedo);
  cJSON *p = cJSON_AddObjectToObject(o, "params");
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    const char *name = model_material_param_name(id);
    if (colours == 1) {
      cJSON_AddNumberToObject(p, name, t->params[id][0]);
    } else {
      cJSON *a = cJSON_AddArrayToObject(p, name);
      for (int c = 0; c < colours; c++)
        cJSON_AddItemToArray(a, cJSON_CreateNumber(t->params[id][c]));
    }
  }
  return o;
}

static int worse_first(const void *a, const void *b) {
  double x = (*(const nbrdf_verify_texel *const *)a)->lobe_error;
  double y = (*(const nbrdf_verify_texel *const *)b)->lobe_error;
  return (x < y) - (x > y);
}

static cJSON *build(const nbrdf_verify_report *r, const char *texture, size_t worst) {
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "texture", texture);
  cJSON_AddNumberToObject(root, "width", r->width);
  cJSON_AddNumberToObject(root, "height", r->height);
  cJSON_AddNumberToObject(root, "levels", r->levels);
  cJSON_AddNumberToObject(root, "colours", r->colours);
  cJSON_AddNumberToObject(root, "lobe_res", NBRDF_LOBE_RES);
  cJSON *th = cJSON_AddArrayToObject(root, "theta_i_deg");
  for (int t = 0; t < VERIFY_N_THETA; t++)
    cJSON_AddItemToArray(th, cJSON_CreateNumber(verify_theta_deg[t]));
  cJSON *ph = cJSON_AddArrayToObject(root, "phi_i_deg");
  for (int t = 0; t < VERIFY_N_THETA; t++)
    cJSON_AddItemToArray(ph, cJSON_CreateNumber(verify_phi_deg[t]));
  cJSON_AddNumberToObject(root, "walks_per_image", r->walks);
  cJSON_AddNumberToObject(root, "reference_runs", 2);
  cJSON_AddNumberToObject(root, "seed", (double)r->seed);
  cJSON_AddItemToObject(root, "overall", summary(&r->overall));
  cJSON *lv = cJSON_AddArrayToObject(root, "per_level");
  for (int l = 0; l < r->n_levels; l++)
    cJSON_AddItemToArray(lv, summary(&r->per_level[l]));
  cJSON_AddNumberToObject(root, "references", (double)r->references);
  cJSON_AddNumberToObject(root, "decoded_latents", (double)r->decoded);
  cJSON_AddNumberToObject(root, "decoder_queries", (double)r->decoder_queries);
  cJSON_AddStringToObject(root, "decoder", r->decoder.own ? "own" : "bundle");
  if (r->decoder.own) {
    cJSON_AddNumberToObject(root, "decoder_bytes", (double)r->decoder.size);
    cJSON_AddStringToObject(root, "decoder_checksum", r->decoder.checksum);
  }
  cJSON_AddNumberToObject(root, "clamped_parameters", (double)r->clamped);
  cJSON_AddNumberToObject(root, "below_trained_alpha", (double)r->below_trained_alpha);
  cJSON_AddBoolToObject(root, "texture_clamps_alpha",
                        r->below_trained_alpha && r->alpha_clamped_by_texture);
  cJSON_AddNumberToObject(root, "reference_seconds", r->reference_seconds);
  cJSON_AddNumberToObject(root, "decode_seconds", r->decode_seconds);
  number(root, "max_albedo", r->max_albedo);
  const nbrdf_verify_texel **order = malloc(sizeof *order * (r->n_texels ? r->n_texels : 1));
  if (!order) {
    cJSON_Delete(root);
    return NULL;
  }
  for (size_t i = 0; i < r->n_texels; i++)
    order[i] = &r->texels[i];
  qsort(order, r->n_texels, sizeof *order, worse_first);
  size_t n = worst && worst < r->n_texels ? worst : r->n_texels;
  cJSON *tx = cJSON_AddArrayToObject(root, "texels");
  for (size_t i = 0; i < n; i++)
    cJSON_AddItemToArray(tx, texel(order[i], r->colours));
  free(order);
  return root;
}

nbrdf_status verify_write_json_to(const nbrdf_verify_report *report, const char *texture,
                                 size_t worst, core_output_file *f, nbrdf_error *err) {
  const char *path = f->path;
  if (!report || !texture || !path)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "verify json: report, texture and path required");
  cJSON *root = build(report, texture, worst);
  char *text = root ? cJSON_Print(root) : NULL;
  cJSON_Delete(root);
  if (!text) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory for the JSON", path);
  size_t len = strlen(text);
  text[len] = '\n'; /* replaces the terminator: written by length */
  nbrdf_status st = core_output_file_pwrite(f, text, len + 1, 0, err);
  free(text);
  return st;
}

nbrdf_status nbrdf_verify_write_json(const nbrdf_verify_report *report, const char *texture,
                                     size_t worst, const char *path, nbrdf_error *err) {
  if (!report || !texture || !path)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "verify json: report, texture and path required");
  core_output_file f;
  const char *inputs[1] = {texture};
  nbrdf_status st = core_output_file_open(&f, path, inputs, 1, err);
  if (st != NBRDF_OK) return st;
  st = verify_write_json_to(report, texture, worst, &f, err);
  if (st != NBRDF_OK) {
    core_output_file_abort(&f);
    return st;
  }
  return core_output_file_commit(&f, err);
}
