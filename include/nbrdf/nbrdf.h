/* nbrdf: neural layered BRDFs (Fan et al. 2022) as a C toolkit. Umbrella header. */
#ifndef NBRDF_H
#define NBRDF_H

#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The library's version, "MAJOR.MINOR.PATCH". */
const char *nbrdf_version(void);

/* The BLAS kernels the networks run on. OpenBLAS chooses them once, when it loads, from the
 * CPU model or from $OPENBLAS_CORETYPE; on CPUs it does not recognise (newer AMD with
 * AVX-512) it falls back to AVX2 kernels at about half the GEMM rate, and on a virtual CPU
 * reporting a generic model name to its SSE3 "Prescott" kernels. A program linking
 * nbrdf that wants the wider kernels sets OPENBLAS_CORETYPE=<wider_core> in the environment
 * of the process before it starts (the nbrdf CLI re-executes itself once to do so). */
typedef struct nbrdf_blas_info {
  const char *core;       /* OpenBLAS's kernels in use, e.g. "Zen", "Haswell", "SkylakeX" */
  const char *config;     /* OpenBLAS's build configuration string */
  int cpu_avx512;         /* the CPU and OS support AVX-512 F/CD/BW/DQ/VL */
  const char *wider_core; /* core type with wider vectors for this CPU (SkylakeX with
                             AVX-512, Haswell with AVX2+FMA), or NULL when the
                             loaded kernels are as wide as the CPU allows or when
                             $OPENBLAS_CORETYPE is set (the user's choice stands) */
} nbrdf_blas_info;
void nbrdf_blas_info_get(nbrdf_blas_info *out);

#ifdef __cplusplus
}
#endif
#endif
