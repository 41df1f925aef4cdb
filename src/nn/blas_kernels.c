#include "nn/blas_kernels.h"
#include "nbrdf/nbrdf.h"

#include <stdlib.h>

#include <cblas.h>
#include <stddef.h>
#include <strings.h>

int nn_cpu_has_avx512(void) {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  /* libgcc's checks include the OS's XSAVE support for the AVX-512 state (XCR0), so a
   * kernel that does not save the registers reports no AVX-512. */
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
         __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512vl");
#else
  return 0;
#endif
}

int nn_cpu_has_avx2(void) {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return 0;
#endif
}

static int core_in(const char *core, const char *const *names, size_t n) {
  for (size_t i = 0; core && i < n; i++)
    if (!strcasecmp(core, names[i])) return 1;
  return 0;
}

int nn_blas_core_is_avx512(const char *core) {
  /* OpenBLAS 0.3.21's AVX-512 kernel families. */
  static const char *const wide[] = {"SkylakeX", "Cooperlake", "SapphireRapids"};
  return core_in(core, wide, sizeof wide / sizeof wide[0]);
}

int nn_blas_core_is_avx2(const char *core) {
  /* OpenBLAS 0.3.21's kernel families with 256-bit FMA sgemm, AVX-512 ones included. */
  static const char *const wide[] = {"Haswell", "Zen", "SkylakeX", "Cooperlake", "SapphireRapids"};
  return core_in(core, wide, sizeof wide / sizeof wide[0]);
}

const char *nn_blas_wider_core(const char *core, int cpu_avx512, int cpu_avx2,
                               const char *env_coretype) {
  if (env_coretype && env_coretype[0]) return NULL; /* the user's choice stands */
  if (!core) return NULL;
  /* SkylakeX needs only F/CD/BW/DQ/VL; Cooperlake and SapphireRapids need more (BF16,
   * AMX) and are kept only when OpenBLAS chose them itself. */
  if (cpu_avx512) return nn_blas_core_is_avx512(core) ? NULL : "SkylakeX";
  /* A CPU whose model OpenBLAS does not know (a VM reporting a generic "Xeon Processor")
   * gets Prescott's SSE3 kernels even when it has AVX2 and FMA. */
  if (cpu_avx2) return nn_blas_core_is_avx2(core) ? NULL : "Haswell";
  return NULL;
}

const char *nn_blas_core(void) { return openblas_get_corename(); }
const char *nn_blas_config(void) { return openblas_get_config(); }

void nbrdf_blas_info_get(nbrdf_blas_info *out) {
  out->core = nn_blas_core();
  out->config = nn_blas_config();
  out->cpu_avx512 = nn_cpu_has_avx512();
  out->wider_core = nn_blas_wider_core(out->core, out->cpu_avx512, nn_cpu_has_avx2(),
                                       getenv("OPENBLAS_CORETYPE"));
}
