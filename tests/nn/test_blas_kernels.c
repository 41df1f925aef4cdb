/* The choice of wider BLAS kernels, as a pure function of the CPU's AVX-512, the kernels
 * OpenBLAS loaded and the user's $OPENBLAS_CORETYPE; and the kernels actually loaded are
 * reported. The CLI's re-execution is tested in tests/cli/test_blas_kernels.sh. */
#include <stdlib.h>
#include <string.h>

#include "nbrdf/nbrdf.h"
#include "nn/blas_kernels.h"
#include "testing.h"

static void test_wider_core(void) {
  /* An AVX-512 CPU on AVX2 kernels (Zen 4/5 under OpenBLAS 0.3.21): SkylakeX. */
  CHECK(nn_blas_wider_core("Haswell", 1, 1, NULL) &&
        !strcmp(nn_blas_wider_core("Haswell", 1, 1, NULL), "SkylakeX"));
  CHECK(nn_blas_wider_core("Zen", 1, 1, "") && !strcmp(nn_blas_wider_core("Zen", 1, 1, ""), "SkylakeX"));
  CHECK(nn_blas_wider_core("Sandybridge", 1, 1, NULL) != NULL);
  /* Already AVX-512 kernels, whatever the spelling. */
  CHECK(nn_blas_wider_core("SkylakeX", 1, 1, NULL) == NULL);
  CHECK(nn_blas_wider_core("skylakex", 1, 1, NULL) == NULL);
  CHECK(nn_blas_wider_core("Cooperlake", 1, 1, NULL) == NULL);
  CHECK(nn_blas_wider_core("SapphireRapids", 1, 1, NULL) == NULL);
  /* No AVX-512: nothing wider to run. */
  CHECK(nn_blas_wider_core("Haswell", 0, 0, NULL) == NULL);
  CHECK(nn_blas_wider_core("Zen", 0, 0, NULL) == NULL);
  /* An AVX2 CPU OpenBLAS does not recognise (generic VM model): Prescott -> Haswell. */
  CHECK(nn_blas_wider_core("Prescott", 0, 1, NULL) &&
        !strcmp(nn_blas_wider_core("Prescott", 0, 1, NULL), "Haswell"));
  CHECK(nn_blas_wider_core("Sandybridge", 0, 1, NULL) &&
        !strcmp(nn_blas_wider_core("Sandybridge", 0, 1, NULL), "Haswell"));
  CHECK(nn_blas_wider_core("Prescott", 1, 1, NULL) &&
        !strcmp(nn_blas_wider_core("Prescott", 1, 1, NULL), "SkylakeX"));
  CHECK(nn_blas_wider_core("Zen", 0, 1, NULL) == NULL);
  CHECK(nn_blas_wider_core("Prescott", 0, 0, NULL) == NULL);
  /* The user chose: their choice stands. */
  CHECK(nn_blas_wider_core("Haswell", 1, 1, "Haswell") == NULL);
  CHECK(nn_blas_wider_core(NULL, 1, 1, NULL) == NULL);
  CHECK(nn_blas_core_is_avx512("SkylakeX") && !nn_blas_core_is_avx512("Zen") &&
        !nn_blas_core_is_avx512(NULL));
}

static void test_info(void) {
  nbrdf_blas_info info;
  nbrdf_blas_info_get(&info);
  CHECK(info.core && info.core[0] && info.config && strstr(info.config, "OpenBLAS"));
  CHECK(info.cpu_avx512 == nn_cpu_has_avx512());
  /* Consistent with the pure rule on this machine. */
  const char *env = getenv("OPENBLAS_CORETYPE");
  const char *want = nn_blas_wider_core(info.core, info.cpu_avx512, nn_cpu_has_avx2(), env);
  CHECK((want == NULL) == (info.wider_core == NULL));
  /* Kernels the CPU cannot run are never proposed. */
  if (!info.cpu_avx512) CHECK(info.wider_core == NULL && !nn_blas_core_is_avx512(info.core));
}

int main(void) {
  RUN(test_wider_core);
  RUN(test_info);
  return testing_finish();
}
