/* The range check: a first pass over a bake's sources, before any network work, that finds
 * every parameter outside the model's trained range at once and reports each in the units
 * the user typed (nbrdf_bake_range), then refuses under NBRDF_RANGE_REFUSE. */
#ifndef NBRDF_BAKE_BAKE_RANGE_H
#define NBRDF_BAKE_BAKE_RANGE_H

#include "nbrdf/bake.h"
#include "texture/param_source.h"

/* Reads every source once more (maps band by band, a constant once), counts per parameter
 * the texels below and above the trained range (a texel once whatever its channels, a
 * constant once) and reports each parameter with any through o->range_report (else
 * o->warning). Then fails, naming the file and the first texel in the bake's order (rows,
 * texels, channels, parameters), where a value is refused: outside the range under REFUSE,
 * or invalid or unphysical under either policy. Maps of differing sizes or larger than a
 * texture may be are left to the bake's own checks (not scanned). Cancel (o->cancel) is seen
 * between bands. */
nbrdf_status bake_range_check(const nbrdf_model *model, texture_param_source **src,
                              const nbrdf_bake_options *o, nbrdf_error *err);

/* "alpha1 map a.png: texel (3, 5) channel G" style location of a value, or "alpha1
 * (constant)": what a refused value's message starts with. */
void bake_source_where(texture_param_source **src, int id, int x, int y, int c, char *buf,
                       size_t n);

#endif
