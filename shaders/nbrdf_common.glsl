// nbrdf shaders: small numerics shared by the other files (GLSL 450).
//
// GLSL has no expm1/log1p. The decoder's log1p output and the proxy's truncated
// Gaussian need them where the plain formulas cancel (f ≈ 0, σ large), so they
// are written with Kahan's correction; `precise` keeps the compiler from
// folding the correction away.
#ifndef NBRDF_COMMON_GLSL
#define NBRDF_COMMON_GLSL

const float NBRDF_PI = 3.14159265358979323846;

// exp(x) - 1 without cancellation near 0 (Kahan: (u - 1) * x / log(u)).
float nbrdf_expm1(float x) {
  precise float u = exp(x);
  if (u == 1.0) return x;
  precise float um1 = u - 1.0;
  if (um1 == -1.0) return -1.0;
  if (abs(x) > 0.5) return um1;
  return um1 * x / log(u);
}

// log(1 + x) without cancellation near 0 (Goldberg: x * log(u) / (u - 1)).
float nbrdf_log1p(float x) {
  precise float u = 1.0 + x;
  if (u == 1.0) return x;
  precise float um1 = u - 1.0;
  return log(u) * x / um1;
}

#endif
