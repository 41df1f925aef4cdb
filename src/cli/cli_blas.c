#include "cli/cli_blas.h"

#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "nbrdf/nbrdf.h"
#include "nn/blas_kernels.h"

/* Set in the re-executed process's environment: the guard against a second re-execution,
 * and the record of what this process asked OpenBLAS for. */
#define CHOSEN_VAR "NBRDF_BLAS_CHOSEN"

void cli_blas_prefer_wide(char **argv) {
  if (getenv(CHOSEN_VAR)) return;
  const char *force = getenv("NBRDF_BLAS_CORETYPE");
  if (force && !strcasecmp(force, "keep")) return;
  nbrdf_blas_info info;
  nbrdf_blas_info_get(&info);
  if (force && force[0] && nn_blas_core_is_avx512(force) && !info.cpu_avx512) {
    fprintf(stderr,
            "nbrdf: NBRDF_BLAS_CORETYPE=%s needs AVX-512, which this CPU lacks; "
            "keeping OpenBLAS's %s kernels\n",
            force, info.core);
    return;
  }
  const char *want = force && force[0] ? force : info.wider_core;
  if (!want || !strcasecmp(want, info.core)) return;
  if (setenv("OPENBLAS_CORETYPE", want, 1) != 0 || setenv(CHOSEN_VAR, want, 1) != 0) return;
  execv("/proc/self/exe", argv);
  /* No /proc, or no exec permission: the loaded kernels are correct, only slower. */
  unsetenv("OPENBLAS_CORETYPE");
  unsetenv(CHOSEN_VAR);
}

void cli_blas_describe(FILE *out) {
  nbrdf_blas_info info;
  nbrdf_blas_info_get(&info);
  const char *chosen = getenv(CHOSEN_VAR);
  fprintf(out, "BLAS: %s; kernels %s", info.config, info.core);
  if (chosen)
    fprintf(out, " (chosen by nbrdf: OPENBLAS_CORETYPE=%s)", chosen);
  else if (getenv("OPENBLAS_CORETYPE"))
    fprintf(out, " (OPENBLAS_CORETYPE=%s from the environment)", getenv("OPENBLAS_CORETYPE"));
  fprintf(out, "; CPU AVX-512: %s", info.cpu_avx512 ? "yes" : "no");
  if (info.wider_core) fprintf(out, "; wider kernels available: %s", info.wider_core);
  fputc('\n', out);
}
