/* The layered material the model represents: a dielectric coat (alpha1, eta)
 * over a slab (albedo, sigma_t) over a conductor (alpha2, r0). Its six
 * parameters' ids, names, conventions, ranges, clamping and quantisation, and
 * the one constructor of its ground truth, in one place so that bake, eval,
 * verify, render, the training draws and the fits cannot drift apart. The ids,
 * the roughness convention and the sigma_t maximum are public
 * (include/nbrdf/model.h).
 *
 * - roughness: the model is trained on GGX alpha; a perceptual roughness r is
 *   alpha = r^2, and textures record which one they were baked from as
 *   roughness=alpha|perceptual in their settings (docs/LATENT-TEXTURE.md);
 * - sigma_t: trained on the paper's {0, 1, 2, NBRDF_BAKE_SIGMA_T_MAX}; the
 *   range policy applies above it. How the layering network sees sigma_t is
 *   the network's own business (model_layering_sigma_t_input, layering.h).
 *
 * Three ranges, and who clamps to which (model_material_range):
 * - the trained range (model_material_ranges: the bundle's base-table grids for
 *   alpha1, eta, alpha2, r0; [0, 1] for albedo; [0, NBRDF_BAKE_SIGMA_T_MAX]):
 *   what the networks saw. A bake and `eval --model neural` clamp to it (or
 *   refuse) value by value, model_material_prepare; the bake's ground truth is
 *   then that of the clamped values, what the texel's latent stands for;
 * - the ground truth's domain (NBRDF_GT_*, include/nbrdf/brdf.h): verify
 *   compares a texel with the truth of the values as painted, clamped only
 *   where the truth cannot represent them;
 * - none: render's reference mode and `eval` of a layered BRDF take the
 *   values as typed; the ground truth refuses what it cannot represent. */
#ifndef NBRDF_MODEL_MATERIAL_H
#define NBRDF_MODEL_MATERIAL_H

#include <stddef.h>

#include "nbrdf/brdf.h"
#include "nbrdf/model.h"

#define MODEL_MATERIAL_PARAMS NBRDF_BAKE_PARAM_COUNT

/* "alpha1", "eta", "alpha2", "r0", "albedo", "sigma_t"; "parameter" for any other id. */
const char *model_material_param_name(int id);

/* The GGX alpha of roughness value `r` read under `convention`. In double:
 * for a float r, (float) of the result equals the float product r * r (the
 * double product of two floats is exact), so float callers get the bytes
 * they always had. */
double model_roughness_alpha(nbrdf_roughness convention, double r);

/* "alpha" or "perceptual", as settings strings and command lines spell them. */
const char *model_roughness_name(nbrdf_roughness convention);

/* The convention named `name` ("alpha", "perceptual"); -1 for any other text. */
int model_roughness_parse(const char *name);

/* Parameter `id`'s value v as read (a map's texel, a typed constant) as the
 * material uses it: -0 -> +0 (so equal tuples have equal bytes), then alpha1
 * and alpha2 under the roughness convention. */
float model_material_read(int id, nbrdf_roughness roughness, float v);

/* The trained range [lo[id], hi[id]] of each parameter for `model`. */
void model_material_ranges(const nbrdf_model *model, float lo[MODEL_MATERIAL_PARAMS],
                           float hi[MODEL_MATERIAL_PARAMS]);

typedef enum model_material_verdict {
  MODEL_VALUE_OK = 0,     /* inside the trained range, unchanged */
  MODEL_VALUE_CLAMPED,    /* outside, moved onto the range (CLAMP) */
  MODEL_VALUE_INVALID,    /* NaN, infinite or negative: always refused */
  MODEL_VALUE_UNPHYSICAL, /* r0 or albedo above 1: always refused */
  MODEL_VALUE_OUTSIDE     /* outside the trained range under REFUSE */
} model_material_verdict;

/* The trained range, value by value: applies model_material_read to *v
 * (parameter `id`, as read), then validation (finite and >= 0, r0 and albedo
 * at most 1) and the range policy (CLAMP moves it onto [lo, hi], REFUSE
 * fails); *v is the value to use when the verdict is OK or CLAMPED. *read
 * (may be NULL) receives the value after the roughness convention and before
 * any clamping (what a warning should show). */
model_material_verdict model_material_prepare(const float *lo, const float *hi, int id,
                                              nbrdf_roughness roughness, nbrdf_range_policy range,
                                              float *v, float *read);

/* The error of a refused verdict: "<at> = <typed> is ...", status
 * NBRDF_ERR_ARGUMENT. `typed` is the value as the user wrote it; under the
 * perceptual convention alpha1 and alpha2 are shown as typed, with alpha =
 * r^2 and the range in r beside them, so the message never shows a number
 * the user did not write without saying where it came from. */
nbrdf_status model_material_fail(model_material_verdict verdict, const float *lo, const float *hi,
                                 int id, nbrdf_roughness roughness, const char *at, float typed,
                                 nbrdf_error *err);

/* The clamp warning shared by bake and eval: "<name>: <what> outside the
 * model's trained range [lo, hi] <was|were> clamped". */
void model_material_clamp_warning(char *buf, size_t cap, const char *name, const float *lo,
                                  const float *hi, int id, const char *what, int plural);

/* v mapped onto [0, 1] over the trained range, in the warped scale of the
 * quantisation (sqrt for alpha, log1p for sigma_t): the space in which the
 * accuracy levels measure distances between tuples. */
float model_material_normalise(const float *lo, const float *hi, int id, float v);

/* The value whose normalised coordinate is u: the inverse of model_material_normalise. */
float model_material_unnormalise(const float *lo, const float *hi, int id, double u);

/* 2^bits levels over the trained range (nbrdf_bake_options.quantise_bits),
 * spaced in the same warped scale; the ends of the range are levels. */
float model_material_quantise(const float *lo, const float *hi, int id, int bits, float v);

/* Which range a whole tuple is clamped to before its ground truth (see the
 * top of this file for who uses which, and why). */
typedef enum model_material_range {
  MODEL_RANGE_NONE = 0, /* as given: the ground truth refuses what it cannot represent */
  MODEL_RANGE_TRUTH,    /* the ground truth's domain: NBRDF_GT_*, r0 and albedo [0, 1] */
  MODEL_RANGE_TRAINED   /* [lo, hi] of model_material_ranges */
} model_material_range;

/* Clamps the six values p (after model_material_read) onto `range` in float
 * (lo, hi: the trained range, read only for MODEL_RANGE_TRAINED); returns how
 * many values moved. A NaN counts as moved and becomes the upper end. */
size_t model_material_clamp(model_material_range range, const float *lo, const float *hi,
                            float p[MODEL_MATERIAL_PARAMS]);

/* The ground-truth layered BRDF of the six values p (GGX alpha, not
 * perceptual roughness; in double so that a caller holding doubles, render's
 * reference mode, passes them unrounded): a conductor (alpha2, r0) under a
 * layered coat (alpha1, eta, albedo, sigma_t), as nbrdf_brdf_create_conductor
 * and nbrdf_brdf_create_layered check and build them. */
nbrdf_status model_material_truth(const double p[MODEL_MATERIAL_PARAMS], nbrdf_brdf **out,
                                  nbrdf_error *err);

#endif
