/* "Both rates": a bench reports its figures on the BLAS kernels OpenBLAS chose and, where
 * the CPU supports wider ones (src/nn/blas_kernels.h: AVX-512 CPUs that OpenBLAS 0.3.21
 * runs on AVX2 kernels), again on those, by running itself a second time with
 * OPENBLAS_CORETYPE set (OpenBLAS reads it only when it loads). `--kernels NAME` asks for
 * that second run on any named kernels, e.g. to compare Sandybridge on an AVX2 machine. */
#ifndef NBRDF_BENCH_KERNELS_H
#define NBRDF_BENCH_KERNELS_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "nbrdf/nbrdf.h"

/* Removes "--kernels NAME" from argv (so the bench's own parser never sees it) and returns
 * NAME, or NULL. */
static inline const char *bench_kernels_take_option(int *argc, char **argv) {
  const char *name = NULL;
  int j = 1;
  for (int i = 1; i < *argc; i++) {
    if (!strcmp(argv[i], "--kernels") && i + 1 < *argc)
      name = argv[++i];
    else
      argv[j++] = argv[i];
  }
  *argc = j;
  argv[j] = NULL;
  return name;
}

/* Prints the kernels in use. In the first run, decides the second one's kernels (`asked`,
 * else the wider kernels of this CPU) and returns them, or NULL when there is none. */
static inline const char *bench_kernels_header(const char *asked) {
  nbrdf_blas_info info;
  nbrdf_blas_info_get(&info);
  int second = getenv("NBRDF_BENCH_SECOND_KERNELS") != NULL;
  printf("BLAS kernels: %s (CPU AVX-512: %s)%s\n\n", info.core, info.cpu_avx512 ? "yes" : "no",
         second ? ", second run" : "");
  fflush(stdout);
  if (second) return NULL;
  return asked ? asked : info.wider_core;
}

/* Runs this bench again (argv without --kernels) on `core`'s kernels; returns its exit
 * status. */
static inline int bench_kernels_rerun(const char *core, char **argv) {
  printf("\n== the same on OPENBLAS_CORETYPE=%s ==\n", core);
  fflush(stdout);
  pid_t pid = fork();
  if (pid == 0) {
    setenv("OPENBLAS_CORETYPE", core, 1);
    setenv("NBRDF_BENCH_SECOND_KERNELS", "1", 1);
    execv("/proc/self/exe", argv);
    perror("bench: re-exec");
    _exit(127);
  }
  int status = 1;
  if (pid < 0 || waitpid(pid, &status, 0) < 0) return 1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

#endif
