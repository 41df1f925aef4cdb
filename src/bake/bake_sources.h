/* Opening a bake's parameter sources: shared by nbrdf_bake and nbrdf verify. */
#ifndef NBRDF_BAKE_BAKE_SOURCES_H
#define NBRDF_BAKE_BAKE_SOURCES_H

#include "nbrdf/bake.h"
#include "texture/param_source.h"

/* Opens the six sources of `in` as nbrdf_bake reads them (maps of r0 and
 * albedo as colour data); `nbrdf verify` opens them the same way. On failure
 * the caller frees whatever sources were opened. */
nbrdf_status bake_open_sources(const nbrdf_bake_inputs *in, nbrdf_param_source **src,
                               nbrdf_error *err);

#endif
