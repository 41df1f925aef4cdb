/* The error the accuracy levels report: a fit's lobes against the held-out
 * tuples' ground truth, beside the universal networks' on the same tuples. */
#ifndef NBRDF_BAKE_BAKE_HELDOUT_H
#define NBRDF_BAKE_BAKE_HELDOUT_H

#include <stddef.h>
#include <stdint.h>

#include "bake/bake_compact.h"
#include "bake/bake_fit.h"
#include "bake/bake_tuple.h"

/* Median lobe error (fraction) over n held-out tuples against their images
 * (bake_truth_lobes, res x res): with the correction (*fitted; with `compact`
 * non-NULL, its coordinates decoded by its student) and with the universal
 * networks alone (*fast). c NULL: only *fast. per_tuple (may be
 * NULL) receives 2n values: fitted then fast errors. `seed`: the bake's,
 * whose azimuths (bake_lobe_azimuth) the networks are asked at. */
nbrdf_status bake_heldout_error(const nbrdf_model *model, const bake_correction *c,
                                const bake_compact *compact, const bake_tuple *t, size_t n,
                                const double *images, int res, uint64_t seed, double *fitted,
                                double *fast, double *per_tuple, nbrdf_error *err);

#endif
