#include "model/material.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "model/layering.h"

static const char *const param_names[MODEL_MATERIAL_PARAMS] = {"alpha1", "eta",    "alpha2",
                                                               "r0",     "albedo", "sigma_t"};

const char *model_material_param_name(int id) {
  return (unsigned)id < MODEL_MATERIAL_PARAMS ? param_names[id] : "parameter";
}

double model_roughness_alpha(nbrdf_roughness convention, double r) {
  return convention == NBRDF_ROUGHNESS_PERCEPTUAL ? r * r : r;
}

const char *model_roughness_name(nbrdf_roughness convention) {
  return convention == NBRDF_ROUGHNESS_PERCEPTUAL ? "perceptual" : "alpha";
}

int model_roughness_parse(const char *name) {
  if (!strcmp(name, "alpha")) return NBRDF_ROUGHNESS_ALPHA;
  if (!strcmp(name, "perceptual")) return NBRDF_ROUGHNESS_PERCEPTUAL;
  return -1;
}

float model_material_read(int id, nbrdf_roughness roughness, float v) {
  float x = v + 0.0f;
  if (id == NBRDF_BAKE_ALPHA1 || id == NBRDF_BAKE_ALPHA2)
    x = (float)model_roughness_alpha(roughness, x);
  return x;
}

void model_material_ranges(const nbrdf_model *model, float lo[MODEL_MATERIAL_PARAMS],
                           float hi[MODEL_MATERIAL_PARAMS]) {
  int n0, n1;
  const float *a0, *a1;
  nbrdf_model_base_grid(model, NBRDF_BASE_DIELECTRIC, &n0, &a0, &n1, &a1);
  lo[NBRDF_BAKE_ALPHA1] = a0[0], hi[NBRDF_BAKE_ALPHA1] = a0[n0 - 1];
  lo[NBRDF_BAKE_ETA] = a1[0], hi[NBRDF_BAKE_ETA] = a1[n1 - 1];
  nbrdf_model_base_grid(model, NBRDF_BASE_CONDUCTOR, &n0, &a0, &n1, &a1);
  lo[NBRDF_BAKE_ALPHA2] = a0[0], hi[NBRDF_BAKE_ALPHA2] = a0[n0 - 1];
  lo[NBRDF_BAKE_R0] = a1[0], hi[NBRDF_BAKE_R0] = a1[n1 - 1];
  lo[NBRDF_BAKE_ALBEDO] = 0.0f, hi[NBRDF_BAKE_ALBEDO] = 1.0f;
  lo[NBRDF_BAKE_SIGMA_T] = 0.0f, hi[NBRDF_BAKE_SIGMA_T] = NBRDF_BAKE_SIGMA_T_MAX;
}

model_material_verdict model_material_prepare(const float *lo, const float *hi, int id,
                                              nbrdf_roughness roughness, nbrdf_range_policy range,
                                              float *v, float *read) {
  float x = model_material_read(id, roughness, *v);
  *v = x;
  if (read) *read = x;
  if (!isfinite(x) || x < 0.0f) return MODEL_VALUE_INVALID;
  if (x >= lo[id] && x <= hi[id]) return MODEL_VALUE_OK;
  if ((id == NBRDF_BAKE_R0 || id == NBRDF_BAKE_ALBEDO) && x > 1.0f) return MODEL_VALUE_UNPHYSICAL;
  if (range == NBRDF_RANGE_REFUSE) return MODEL_VALUE_OUTSIDE;
  *v = x < lo[id] ? lo[id] : hi[id];
  return MODEL_VALUE_CLAMPED;
}

nbrdf_status model_material_fail(model_material_verdict verdict, const float *lo, const float *hi,
                                 int id, nbrdf_roughness roughness, const char *at, float typed,
                                 nbrdf_error *err) {
  if (roughness == NBRDF_ROUGHNESS_PERCEPTUAL &&
      (id == NBRDF_BAKE_ALPHA1 || id == NBRDF_BAKE_ALPHA2)) {
    double a = model_roughness_alpha(roughness, typed);
    if (verdict == MODEL_VALUE_INVALID)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "%s = %g (perceptual roughness r; alpha = r^2 = %g) is not a finite "
                       "value >= 0",
                       at, (double)typed, a);
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s = %g (perceptual roughness r; alpha = r^2 = %g) is outside the "
                     "model's trained range: r in [%g, %g] (alpha in [%g, %g])",
                     at, (double)typed, a, sqrt((double)lo[id]), sqrt((double)hi[id]),
                     (double)lo[id], (double)hi[id]);
  }
  if (verdict == MODEL_VALUE_INVALID)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s = %g is not a finite value >= 0", at,
                     (double)typed);
  if (verdict == MODEL_VALUE_UNPHYSICAL)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s = %g is above 1 (not physical)", at,
                     (double)typed);
  return core_fail(err, NBRDF_ERR_ARGUMENT, "%s = %g is outside the model's trained range [%g, %g]",
                   at, (double)typed, (double)lo[id], (double)hi[id]);
}

void model_material_clamp_warning(char *buf, size_t cap, const char *name, const float *lo,
                                  const float *hi, int id, const char *what, int plural) {
  snprintf(buf, cap, "%s: %s outside the model's trained range [%g, %g] %s clamped", name, what,
           (double)lo[id], (double)hi[id], plural ? "were" : "was");
}

/* Quantisation levels are spaced evenly where the parameter's effect is
 * about even: alpha in sqrt (perceptual roughness; linear steps would be
 * 40 % of alpha = 0.01 at 8 bits), sigma_t in log(1 + sigma_t) (as the
 * layering network sees it), the rest linearly. The ends of the range are
 * levels, so quantised values stay inside it. */
static float warp(int id, float v) {
  if (id == NBRDF_BAKE_ALPHA1 || id == NBRDF_BAKE_ALPHA2) return sqrtf(v);
  if (id == NBRDF_BAKE_SIGMA_T) return model_layering_sigma_t_input(v);
  return v;
}

static float unwarp(int id, float u) {
  if (id == NBRDF_BAKE_ALPHA1 || id == NBRDF_BAKE_ALPHA2) return u * u;
  if (id == NBRDF_BAKE_SIGMA_T) return expm1f(u);
  return u;
}

float model_material_normalise(const float *lo_, const float *hi_, int id, float v) {
  float lo = warp(id, lo_[id]), hi = warp(id, hi_[id]);
  return hi > lo ? (warp(id, v) - lo) / (hi - lo) : 0.0f;
}

float model_material_unnormalise(const float *lo_, const float *hi_, int id, double u) {
  float lo = warp(id, lo_[id]), hi = warp(id, hi_[id]);
  return unwarp(id, (float)(lo + (hi - lo) * u));
}

float model_material_quantise(const float *lo_, const float *hi_, int id, int bits, float v) {
  float lo = warp(id, lo_[id]), hi = warp(id, hi_[id]);
  if (!(hi > lo)) return v;
  float steps = (float)((1u << bits) - 1);
  float q = roundf((warp(id, v) - lo) / (hi - lo) * steps);
  float r = unwarp(id, lo + (hi - lo) * q / steps);
  /* keep the ends exact (sqrt/square and log1p/expm1 round) */
  return q <= 0 ? lo_[id] : q >= steps ? hi_[id] : r;
}

/* In float, with the bounds compared in double: a value is kept exactly when
 * inside, and an end is the float nearest the bound. */
static float clamp_one(float v, double lo, double hi, size_t *moved) {
  if (v >= lo && v <= hi) return v;
  ++*moved;
  return (float)(v < lo ? lo : hi);
}

size_t model_material_clamp(model_material_range range, const float *lo, const float *hi,
                            float p[MODEL_MATERIAL_PARAMS]) {
  size_t moved = 0;
  if (range == MODEL_RANGE_TRUTH) {
    p[NBRDF_BAKE_ALPHA1] =
        clamp_one(p[NBRDF_BAKE_ALPHA1], NBRDF_GT_ALPHA_MIN, NBRDF_GT_ALPHA_MAX, &moved);
    p[NBRDF_BAKE_ALPHA2] =
        clamp_one(p[NBRDF_BAKE_ALPHA2], NBRDF_GT_ALPHA_MIN, NBRDF_GT_ALPHA_MAX, &moved);
    p[NBRDF_BAKE_ETA] = clamp_one(p[NBRDF_BAKE_ETA], NBRDF_GT_ETA_MIN, NBRDF_GT_ETA_MAX, &moved);
    p[NBRDF_BAKE_R0] = clamp_one(p[NBRDF_BAKE_R0], 0.0, 1.0, &moved);
    p[NBRDF_BAKE_ALBEDO] = clamp_one(p[NBRDF_BAKE_ALBEDO], 0.0, 1.0, &moved);
    p[NBRDF_BAKE_SIGMA_T] = clamp_one(p[NBRDF_BAKE_SIGMA_T], 0.0, NBRDF_GT_SIGMA_T_MAX, &moved);
  } else if (range == MODEL_RANGE_TRAINED) {
    for (int id = 0; id < MODEL_MATERIAL_PARAMS; id++)
      p[id] = clamp_one(p[id], lo[id], hi[id], &moved);
  }
  return moved;
}

nbrdf_status model_material_truth(const double p[MODEL_MATERIAL_PARAMS], nbrdf_brdf **out,
                                  nbrdf_error *err) {
  nbrdf_brdf *bottom = NULL;
  nbrdf_status st =
      nbrdf_brdf_create_conductor(p[NBRDF_BAKE_ALPHA2], p[NBRDF_BAKE_R0], &bottom, err);
  if (st == NBRDF_OK)
    st = nbrdf_brdf_create_layered(p[NBRDF_BAKE_ALPHA1], p[NBRDF_BAKE_ETA], p[NBRDF_BAKE_ALBEDO],
                                   p[NBRDF_BAKE_SIGMA_T], bottom, out, err);
  nbrdf_brdf_destroy(bottom);
  return st;
}
