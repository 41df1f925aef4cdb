/* Finite-difference check of one backward-pass derivative, shared by the
 * gradient tests of every layer that back-propagates. */
#ifndef NBRDF_TESTS_FD_CHECK_H
#define NBRDF_TESTS_FD_CHECK_H

#include <math.h>

#include "testing.h"

/* A scalar function of the current parameter/input values. */
typedef double (*scalar_fn)(void *ctx);

/* Central differences of fn with respect to *p against `analytic`, at step h
 * and then h/4, h/16: a ReLU kink within h of the point spoils the larger
 * steps (measured: one row of a 12-wide decoder had one at ~1e-3), while a
 * wrong gradient matches at none of them. */
static inline void fd_check(const char *what, int index, float *p, double analytic, scalar_fn fn,
                            void *ctx, double h, double scale) {
  float saved = *p;
  double fd[3];
  int ok = 0;
  for (int k = 0; k < 3 && !ok; k++, h /= 4) {
    *p = (float)(saved + h);
    double up = fn(ctx), dp = (double)*p - saved;
    *p = (float)(saved - h);
    double down = fn(ctx), dm = saved - (double)*p;
    *p = saved;
    fd[k] = (up - down) / (dp + dm);
    ok = fabs(fd[k] - analytic) <= 0.03 * fmax(fabs(fd[k]), fabs(analytic)) + 2e-3 * scale;
    if (!ok && k == 2)
      testing_fail(__FILE__, __LINE__, "%s[%d]: backward %.6g, finite differences %.6g %.6g %.6g",
                   what, index, analytic, fd[0], fd[1], fd[2]);
  }
  testing_checks++;
}

#endif
