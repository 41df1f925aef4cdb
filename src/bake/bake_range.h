/* The range check: a first pass over a bake's sources, before any network work, that finds
 * every parameter outside the model's trained range at once and reports each in the units
 * the user typed (nbrdf_bake_range), then refuses under NBRDF_RANGE_REFUSE. */
#ifndef NBRDF_BAKE_BAKE_RANGE_H
#define NBRDF_BAKE_BAKE_RANGE_H

#include "nbrdf/bake.h"
#include "texture/param_source.h"

/* Reads every source once more (maps band by band, a constant once), counts per parameter
 * the texels below and above the trained range (and, for alpha1 and alpha2, below what
 * o->accuracy takes as given: bake_taken_ranges) (a texel once whatever its channels, a
 * constant once) and reports each parameter with any through o->range_report (else
 * o->warning). Then fails, naming the file and the first texel in the bake's order (rows,
 * texels, channels, parameters), where a value is refused: outside the taken range under REFUSE,
 * or invalid or unphysical under either policy. Maps of differing sizes or larger than a
 * texture may be are left to the bake's own checks (not scanned). Cancel (o->cancel) is seen
 * between bands. */
nbrdf_status bake_range_check(const nbrdf_model *model, texture_param_source **src,
                              const nbrdf_bake_options *o, nbrdf_error *err);

/* The lowest GGX alpha (alpha1 and alpha2) a level that fits its own ground truth takes as
 * given: the ground truth's own floor. Below the trained range the universal networks still
 * see the trained minimum (the base tables clamp), but the fit's and the held-out check's
 * ground truth is that of the value as given, so the fit moves the latent toward it. */
#define BAKE_ALPHA_FIT_MIN ((float)NBRDF_GT_ALPHA_MIN)

/* Non-zero for the levels that take alpha1 and alpha2 down to BAKE_ALPHA_FIT_MIN as given:
 * FITTED, SPECIALISED, COMPACT and AUTO (which may climb to them). */
int bake_level_fits_alpha(nbrdf_bake_accuracy a);

/* The range a bake at level `a` takes values from (lo, hi): the trained range
 * (model_material_ranges), with the lower ends of alpha1 and alpha2 at BAKE_ALPHA_FIT_MIN
 * where the level fits them (and the trained minimum is above it). */
void bake_taken_ranges(const nbrdf_model *model, nbrdf_bake_accuracy a, float *lo, float *hi);

/* model_material_quantise over the trained range [lo, hi], except that a value below it (an
 * alpha a fitting level takes as given) is kept as given: the levels span the trained range,
 * whose bytes a quantised bake must not change. */
float bake_quantise(const float *lo, const float *hi, int id, int bits, float v);

/* "alpha1 map a.png: texel (3, 5) channel G" style location of a value, or "alpha1
 * (constant)": what a refused value's message starts with. */
void bake_source_where(texture_param_source **src, int id, int x, int y, int c, char *buf,
                       size_t n);

#endif
