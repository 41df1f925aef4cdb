/* What a public nbrdf_brdf handle is: an immutable internal BSDF (which owns
 * its layered bottom chain). Internal, for the other layers and the tests. */
#ifndef NBRDF_BRDF_HANDLE_H
#define NBRDF_BRDF_HANDLE_H

#include "brdf/bsdf.h"
#include "nbrdf/brdf.h"

struct nbrdf_brdf {
  brdf_bsdf b;
};

static inline const brdf_bsdf *brdf_handle_bsdf(const nbrdf_brdf *brdf) { return &brdf->b; }

/* Checks a direction given through the public API: finite, z > 0, unit length
 * within 1e-6; writes it normalised. `what` names it in the message
 * ("query 3: wo"). */
nbrdf_status brdf_check_direction(const double w[3], const char *what, vec3 *out, nbrdf_error *err);

#endif
