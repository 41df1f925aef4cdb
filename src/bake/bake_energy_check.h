/* The held-out check's energy guard (docs/BAKE.md, "Held-out check"): a fitting level whose
 * decoder creates energy on the tuples the fit saw or held out is worse than fast, however
 * small its lobe error. The lobe error cannot see it: a lobe image (32² pixels) does not
 * resolve an α 0.001 lobe, so a fine-tuned decoder can match the images while its lobe
 * integrates to far more than the light that arrives (measured: decoded albedo 16.7 and 805
 * at α1 0.001, docs/notes/2026-11-29-sharp-alpha.md).
 *
 * The figure is the energy audit's (bake_albedo_precise: the polar rule, the maximum over
 * its six θi up to 89°) of the level's latents decoded by the level's decoder, beside the
 * universal networks' on the same tuples. The level creates energy when its largest value
 * exceeds max(BAKE_AUDIT_LIMIT, fast's largest + BAKE_ENERGY_MARGIN): the audit's own limit,
 * raised to what the fallback would bake where fast itself is above it (falling back then
 * would not remove energy, only lobe accuracy). Compared with fast's decoded albedo rather
 * than the ground truth's: both come from one deterministic rule whose error on a lobe is the
 * same for both decoders to within its measured noise, while the truth's albedo is a Monte
 * Carlo estimate with its own spread, and the question the guard answers is whether the
 * texture is safer at fast. */
#ifndef NBRDF_BAKE_BAKE_ENERGY_CHECK_H
#define NBRDF_BAKE_BAKE_ENERGY_CHECK_H

#include <stddef.h>

#include "bake/bake_compact.h"
#include "bake/bake_fit.h"
#include "bake/bake_tuple.h"

/* The polar rule's measured spread against brute force (BAKE_AUDIT_NOISE, docs/BAKE.md
 * "Energy audit"): how far the level may read above fast before it counts as creating
 * energy where fast is itself above the limit. */
#define BAKE_ENERGY_MARGIN 0.03

/* The largest decoded directional albedo over the n tuples `t` (the maximum over the audit's
 * θi): *level_max with the correction c (its fine-tuned decoder, or with `compact` non-NULL
 * its student on the compact coordinates), *fast_max with the universal networks alone;
 * *worst (may be NULL) the index of the tuple of *level_max. */
nbrdf_status bake_energy_measure(const nbrdf_model *model, const bake_correction *c,
                                 const bake_compact *compact, const bake_tuple *t, size_t n,
                                 double *level_max, double *fast_max, size_t *worst,
                                 nbrdf_error *err);

/* max(BAKE_AUDIT_LIMIT, fast_max + BAKE_ENERGY_MARGIN). */
double bake_energy_limit(double fast_max);

/* Non-zero when level_max exceeds bake_energy_limit(fast_max) (NaN counts as exceeding). */
int bake_energy_creates(double level_max, double fast_max);

#endif
