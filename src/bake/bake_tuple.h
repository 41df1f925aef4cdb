/* What a bake does with one parameter tuple, in one place, so that every
 * caller computes the same latent for the same values: `nbrdf bake` per
 * texel (bake_band.c) and `nbrdf eval --model neural` per CSV row.
 *
 * A value goes through: -0 -> +0; the roughness convention (alpha1, alpha2:
 * alpha = r^2 under NBRDF_ROUGHNESS_PERCEPTUAL); validation (finite and
 * >= 0, r0 and albedo at most 1); the trained range (the model's table grids
 * for alpha1, eta, alpha2, r0; [0, 1] for albedo; [0, NBRDF_BAKE_SIGMA_T_MAX]
 * for sigma_t) under the range policy (CLAMP moves it onto the range, REFUSE
 * fails); optional quantisation. The tuple then goes through the base tables,
 * the layering network and the sampling network. */
#ifndef NBRDF_BAKE_BAKE_TUPLE_H
#define NBRDF_BAKE_BAKE_TUPLE_H

#include <stddef.h>

#include "nbrdf/bake.h"
#include "nbrdf/model.h"

/* A tuple: alpha1, eta, alpha2, r0, albedo, sigma_t (after the roughness
 * convention and any clamping). */
typedef struct bake_tuple {
  float p[NBRDF_BAKE_PARAM_COUNT];
} bake_tuple;

/* The trained range [lo[id], hi[id]] of each parameter for `model`. */
void bake_ranges_init(const nbrdf_model *model, float lo[NBRDF_BAKE_PARAM_COUNT],
                      float hi[NBRDF_BAKE_PARAM_COUNT]);

typedef enum bake_verdict {
  BAKE_VALUE_OK = 0,     /* inside the trained range, unchanged */
  BAKE_VALUE_CLAMPED,    /* outside, moved onto the range (CLAMP) */
  BAKE_VALUE_INVALID,    /* NaN, infinite or negative: always refused */
  BAKE_VALUE_UNPHYSICAL, /* r0 or albedo above 1: always refused */
  BAKE_VALUE_OUTSIDE     /* outside the trained range under REFUSE */
} bake_verdict;

/* Applies the conventions above to *v (parameter `id`, as read) up to the
 * range policy; *v is the value to use when the verdict is OK or CLAMPED. */
bake_verdict bake_value_prepare(const float *lo, const float *hi, int id, nbrdf_roughness roughness,
                                nbrdf_range_policy range, float *v);
/* As above; *read (not NULL) also receives the value after the roughness
 * convention and before any clamping (what a warning should show). */
bake_verdict bake_value_prepare_read(const float *lo, const float *hi, int id,
                                     nbrdf_roughness roughness, nbrdf_range_policy range, float *v,
                                     float *read);

/* The error of a refused verdict: "<at> = <typed> is ...", status
 * NBRDF_ERR_ARGUMENT. `typed` is the value as the user wrote it; under the
 * perceptual convention alpha1 and alpha2 are shown as typed, with alpha =
 * r^2 and the range in r beside them, so the message never shows a number
 * the user did not write without saying where it came from. */
nbrdf_status bake_value_fail(bake_verdict verdict, const float *lo, const float *hi, int id,
                             nbrdf_roughness roughness, const char *at, float typed,
                             nbrdf_error *err);

/* v mapped onto [0, 1] over the trained range, in the warped scale of the
 * quantisation (sqrt for alpha, log1p for sigma_t): the space in which the
 * accuracy levels measure distances between tuples. */
float bake_value_normalise(const float *lo, const float *hi, int id, float v);

/* 2^bits levels over the trained range (nbrdf_bake_options.quantise_bits). */
float bake_value_quantise(const float *lo, const float *hi, int id, int bits, float v);

/* The clamp warning shared by bake and eval: "<name>: <what> outside the
 * model's trained range [lo, hi] <was|were> clamped". */
void bake_clamp_warning(char *buf, size_t cap, const char *name, const float *lo, const float *hi,
                        int id, const char *what, int plural);

/* Latent (D floats), then sigma and w of the proxy, of n prepared tuples:
 * tuple t[idx[k]] (idx NULL: t[k]) goes to out + idx[k] * (D + 2) (idx NULL:
 * out + k * (D + 2)). */
nbrdf_status bake_tuples_evaluate(const nbrdf_model *model, const bake_tuple *t, const size_t *idx,
                                  size_t n, float *out, nbrdf_error *err);
/* The same with the layering and sampling networks on `gpu` (its layering and sampler
 * uploaded; NULL: the CPU, as bake_tuples_evaluate). */
struct model_gpu;
nbrdf_status bake_tuples_evaluate_on(const nbrdf_model *model, const struct model_gpu *gpu,
                                     const bake_tuple *t, const size_t *idx, size_t n, float *out,
                                     nbrdf_error *err);

#endif
