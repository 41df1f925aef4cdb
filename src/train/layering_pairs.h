/* Training pairs of the layering network: one per layered BRDF of a data
 * set, its inputs looked up in the base tables exactly as a bake does (so the
 * network also absorbs the tables' interpolation error). A three-layer BRDF
 * (coat over coat over conductor) is a pair whose bottom is itself layered:
 * its latent is L(mid, bottom, A2, σT2), the network applied recursively.
 * One pair in `validation_every` (by order in the data) is held out; both
 * layering losses (train_layering.h) use the same split, so their validation
 * figures compare, and appending three-layer data after two-layer data leaves
 * the two-layer split as it was. */
#ifndef NBRDF_TRAIN_LAYERING_PAIRS_H
#define NBRDF_TRAIN_LAYERING_PAIRS_H

#include <stddef.h>

#include "model/base_table.h"
#include "train/samples.h"

typedef struct train_layering_pairs {
  size_t n;
  float *top, *bottom;     /* [n × D] table latents: outermost coat, conductor */
  float *albedo, *sigma_t; /* [n] outermost coat's medium */
  unsigned char *coats;    /* [n] 1 or 2 */
  float *mid;              /* [n × D] second coat's table latent (coats == 2; else zero) */
  float *albedo2, *sigma_t2;
  float *target; /* [n × D] the decoder run's latents; NULL without latents */
  size_t *brdf;  /* [n] index of the BRDF in the data (its samples) */
} train_layering_pairs;

/* Pairs of the BRDFs with 1 .. max_coats coats. `latents` [data->n_brdfs ×
 * D] may be NULL (no targets). */
nbrdf_status train_layering_pairs_make(const train_samples *data, const float *latents,
                                       const model_base_table t[2], int max_coats,
                                       int validation_every, train_layering_pairs *train,
                                       train_layering_pairs *val, nbrdf_error *err);
void train_layering_pairs_free(train_layering_pairs *p);

#endif
