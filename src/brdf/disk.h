/* Trigonometry-free sampling of the unit disk and sphere for the random
 * walks: a uniform point of the disk by rejection from the square (π/4 of
 * the draws are kept), which gives both a uniform radius² and a uniform
 * direction without sin/cos. Profiling showed sincos at ~10 % of a walk. */
#ifndef NBRDF_BRDF_DISK_H
#define NBRDF_BRDF_DISK_H

#include "core/rng.h"
#include "core/vec3.h"

/* Uniform in the open unit disk; *r2 = x² + y² (uniform in [0, 1)). */
static inline void brdf_disk_sample(core_rng *rng, double *x, double *y, double *r2) {
  double a, b, s;
  do {
    a = 2.0 * core_rng_uniform(rng) - 1.0;
    b = 2.0 * core_rng_uniform(rng) - 1.0;
    s = a * a + b * b;
  } while (s >= 1.0);
  *x = a;
  *y = b;
  *r2 = s;
}

/* Uniform on the unit sphere from a uniform disk point (Marsaglia 1972). */
static inline vec3 brdf_disk_to_sphere(double x, double y, double r2) {
  double k = 2.0 * sqrt(1.0 - r2);
  return v3(x * k, y * k, 1.0 - 2.0 * r2);
}

#endif
