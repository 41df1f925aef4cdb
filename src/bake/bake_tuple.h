/* What a bake does with one parameter tuple, in one place, so that every
 * caller computes the same latent for the same values: `nbrdf bake` per
 * texel (bake_band.c) and `nbrdf eval --model neural` per CSV row.
 *
 * A value is first prepared by the material (model/material.h:
 * model_material_prepare: -0 -> +0, the roughness convention, validation, the
 * trained range under the range policy; model_material_quantise: optional
 * quantisation). The tuple then goes through the base tables, the layering
 * network and the sampling network. */
#ifndef NBRDF_BAKE_BAKE_TUPLE_H
#define NBRDF_BAKE_BAKE_TUPLE_H

#include <stddef.h>

#include "model/material.h"
#include "nbrdf/model.h"

/* A tuple: alpha1, eta, alpha2, r0, albedo, sigma_t (after the roughness
 * convention and any clamping). */
typedef struct bake_tuple {
  float p[NBRDF_BAKE_PARAM_COUNT];
} bake_tuple;

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
