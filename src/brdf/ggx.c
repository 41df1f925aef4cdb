#include "brdf/ggx.h"

int ggx_sample_vndf(double alpha, vec3 w, double u1, double u2, vec3 *m) {
  if (w.z < 0.0) w = v3_neg(w);
  /* Stretch ω to the configuration α = 1, where the visible normals of the
   * unit hemisphere are uniform on a spherical cap around ω (Dupuy & Benyoub
   * 2023, Listing 3), then unstretch the sampled normal. */
  vec3 ws = v3(alpha * w.x, alpha * w.y, w.z);
  double len = v3_length(ws);
  if (!(len > 0.0)) return 0;
  ws = v3_scale(ws, 1.0 / len);
  double phi = 2.0 * M_PI * u1;
  double z = (1.0 - u2) * (1.0 + ws.z) - ws.z;
  double sin_theta = sqrt(fmax(0.0, 1.0 - z * z));
  vec3 h = v3(sin_theta * cos(phi) + ws.x, sin_theta * sin(phi) + ws.y, z + ws.z);
  vec3 mm = v3(alpha * h.x, alpha * h.y, fmax(0.0, h.z));
  double mlen = v3_length(mm);
  if (!(mlen > 0.0)) return 0;
  mm = v3_scale(mm, 1.0 / mlen);
  if (!(mm.z > 0.0)) return 0;
  *m = mm;
  return 1;
}
