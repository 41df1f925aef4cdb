/* Opening a bake's parameter sources: shared by nbrdf_bake and nbrdf verify. */
#ifndef NBRDF_BAKE_BAKE_SOURCES_H
#define NBRDF_BAKE_BAKE_SOURCES_H

#include "nbrdf/bake.h"
#include "texture/param_source.h"

/* Opens the six sources of `in` as nbrdf_bake reads them (maps of r0 and
 * albedo as colour data); `nbrdf verify` opens them the same way. On failure
 * the caller frees whatever sources were opened. */
/* NBRDF_ERR_ARGUMENT unless width x height is 0 x 0 or each in 1..NBRDF_BAKE_SIZE_MAX. */
nbrdf_status bake_check_size(int width, int height, nbrdf_error *err);

/* Opens the six sources and sizes the maps: to in->width x height when
 * given (resampled when in->resample is BILINEAR, else an error for a map of
 * another size), else with BILINEAR to the largest map. */
nbrdf_status bake_open_sources(const nbrdf_bake_inputs *in, texture_param_source **src,
                               nbrdf_error *err);

#endif
