/* Double-precision 3-vectors for the physics code. Shading frame: z is the
 * surface normal, directions point away from the surface. */
#ifndef NBRDF_CORE_VEC3_H
#define NBRDF_CORE_VEC3_H

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct vec3 {
  double x, y, z;
} vec3;

static inline vec3 v3(double x, double y, double z) { return (vec3){x, y, z}; }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_scale(vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline vec3 v3_neg(vec3 a) { return v3(-a.x, -a.y, -a.z); }
static inline double v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b) {
  return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double v3_length(vec3 a) { return sqrt(v3_dot(a, a)); }
static inline vec3 v3_normalize(vec3 a) { return v3_scale(a, 1.0 / v3_length(a)); }
/* Mirror of a direction about the z axis plane (lower <-> upper hemisphere). */
static inline vec3 v3_flip_z(vec3 a) { return v3(a.x, a.y, -a.z); }
static inline int v3_is_finite(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

/* Direction from spherical angles in radians (θ from +z, φ from +x). */
static inline vec3 v3_from_spherical(double theta, double phi) {
  double s = sin(theta);
  return v3(s * cos(phi), s * sin(phi), cos(theta));
}

/* An orthonormal basis (t, b, n) around unit n (Duff et al. 2017). */
static inline void v3_basis(vec3 n, vec3 *t, vec3 *b) {
  double sign = copysign(1.0, n.z);
  double a = -1.0 / (sign + n.z);
  double c = n.x * n.y * a;
  *t = v3(1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x);
  *b = v3(c, sign + n.y * n.y * a, -n.y);
}

#endif
