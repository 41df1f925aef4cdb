/* Which OpenBLAS kernels run, and whether the CPU offers wider ones.
 *
 * Debian's OpenBLAS 0.3.21 (DYNAMIC_ARCH) picks its kernels once, when it loads, from the CPU
 * model it recognises, or from $OPENBLAS_CORETYPE. It does not recognise newer AMD CPUs with
 * AVX-512 (Zen 4/5) and runs its AVX2 "Haswell"/"Zen" kernels there: measured on a Zen 5,
 * sgemm 87 vs 183 GFLOP/s per core with OPENBLAS_CORETYPE=SkylakeX (../shared/ECOSYSTEM-NOTES.md).
 * A library cannot change the kernels after load; a program can set the variable and
 * re-execute itself before its first BLAS call (the nbrdf CLI does, src/cli/cli_blas.c). */
#ifndef NBRDF_NN_BLAS_KERNELS_H
#define NBRDF_NN_BLAS_KERNELS_H

/* 1 when the CPU and the OS support AVX-512 F, CD, BW, DQ and VL: what OpenBLAS's SkylakeX
 * kernels need. */
int nn_cpu_has_avx512(void);

/* 1 when the CPU and the OS support AVX2 and FMA: what OpenBLAS's Haswell kernels need. */
int nn_cpu_has_avx2(void);

/* 1 when OpenBLAS's kernels of that name use AVX-512 (a CPU without it cannot run them). */
int nn_blas_core_is_avx512(const char *core);
/* 1 when they use at least 256-bit FMA (Haswell, Zen and the AVX-512 families). */
int nn_blas_core_is_avx2(const char *core);

/* The OpenBLAS core type that would use wider vectors than `core` on a CPU with AVX-512
 * (`cpu_avx512`: SkylakeX) or AVX2+FMA (`cpu_avx2`: Haswell), or NULL when `core` is already
 * as wide as the CPU allows, the CPU has neither, or the user chose the kernels
 * (`env_coretype` non-NULL and non-empty). A pure function of its arguments, so it is
 * tested without such a CPU. */
const char *nn_blas_wider_core(const char *core, int cpu_avx512, int cpu_avx2,
                               const char *env_coretype);

/* OpenBLAS's name for the kernels it loaded ("Zen", "Haswell", "SkylakeX", ...) and its
 * build configuration string. Both are static strings of OpenBLAS. */
const char *nn_blas_core(void);
const char *nn_blas_config(void);

#endif
