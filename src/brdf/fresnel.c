#include "brdf/fresnel.h"

double brdf_fresnel_dielectric(double cos_i, double eta) {
  cos_i = fmin(1.0, fmax(-1.0, cos_i));
  if (cos_i < 0.0) {
    eta = 1.0 / eta;
    cos_i = -cos_i;
  }
  double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta); /* Snell's law */
  if (sin2_t >= 1.0) return 1.0;                       /* total internal reflection */
  double cos_t = sqrt(fmax(0.0, 1.0 - sin2_t));
  double parl_num = eta * cos_i - cos_t, parl_den = eta * cos_i + cos_t;
  double perp_num = cos_i - eta * cos_t, perp_den = cos_i + eta * cos_t;
  if (!(parl_den > 0.0) || !(perp_den > 0.0)) return 1.0; /* grazing with η = 1 */
  /* (r∥² + r⊥²) / 2 over a common denominator: one division. */
  double a = parl_num * perp_den, b = perp_num * parl_den, den = parl_den * perp_den;
  return 0.5 * (a * a + b * b) / (den * den);
}

int brdf_fresnel_refract(vec3 w, vec3 m, double eta, vec3 *wt, double *etap) {
  double cos_i = v3_dot(m, w);
  if (cos_i < 0.0) { /* arriving from the inside: the interface looks like 1/η */
    eta = 1.0 / eta;
    cos_i = -cos_i;
    m = v3_neg(m);
  }
  double sin2_t = fmax(0.0, 1.0 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0) return 0;
  double cos_t = sqrt(1.0 - sin2_t);
  *wt = v3_add(v3_scale(v3_neg(w), 1.0 / eta), v3_scale(m, cos_i / eta - cos_t));
  *etap = eta;
  return 1;
}
