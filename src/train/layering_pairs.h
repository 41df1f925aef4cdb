/* Training pairs of the layering network: one per two-layer BRDF of a data
 * set, its inputs looked up in the base tables exactly as a bake does (so the
 * network also absorbs the tables' interpolation error). One pair in
 * `validation_every` (by order in the data) is held out; both layering losses
 * (latent and decoded, train_layering.h) use the same split, so their
 * validation figures compare. */
#ifndef NBRDF_TRAIN_LAYERING_PAIRS_H
#define NBRDF_TRAIN_LAYERING_PAIRS_H

#include <stddef.h>

#include "model/base_table.h"
#include "train/samples.h"

typedef struct layering_pairs {
  size_t n;
  float *top, *bottom;     /* [n × D] table latents */
  float *albedo, *sigma_t; /* [n] */
  float *target;           /* [n × D] the decoder run's latents; NULL without latents */
  size_t *brdf;            /* [n] index of the BRDF in the data (its samples) */
} layering_pairs;

/* `latents` [data->n_brdfs × D] may be NULL (no targets). */
nbrdf_status layering_pairs_make(const train_samples *data, const float *latents,
                                 const model_base_table t[2], int validation_every,
                                 layering_pairs *train, layering_pairs *val, nbrdf_error *err);
void layering_pairs_free(layering_pairs *p);

#endif
