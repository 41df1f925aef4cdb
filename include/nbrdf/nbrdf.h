/* nbrdf: neural layered BRDFs (Fan et al. 2022) as a C toolkit. Umbrella header. */
#ifndef NBRDF_H
#define NBRDF_H

#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The library's version, "MAJOR.MINOR.PATCH". */
const char *nbrdf_version(void);

#ifdef __cplusplus
}
#endif
#endif
