/* The CLI runs its networks on the widest BLAS kernels the CPU supports. OpenBLAS reads
 * $OPENBLAS_CORETYPE only when it loads, before main(): so when the loaded kernels are
 * narrower than the CPU allows (src/nn/blas_kernels.h), the CLI sets the variable and
 * re-executes itself, once, before any BLAS call. $NBRDF_BLAS_CORETYPE overrides the
 * choice: a core type name to force, or "keep" for the kernels OpenBLAS chose itself. */
#ifndef NBRDF_CLI_BLAS_H
#define NBRDF_CLI_BLAS_H

#include <stdio.h>

/* Returns only when no re-execution is needed or it failed (then the program goes on with
 * the loaded kernels, which are correct, only slower). */
void cli_blas_prefer_wide(char **argv);
/* One line: the kernels in use, the CPU's AVX-512, and who chose the kernels. */
void cli_blas_describe(FILE *out);

#endif
