#include "brdf/ggx.h"

int brdf_ggx_sample_vndf_disk(double alpha, vec3 w, double x, double y, double r2, vec3 *m) {
  if (w.z < 0.0) w = v3_neg(w);
  /* Stretch ω to the configuration α = 1, where the visible normals of the
   * unit hemisphere are uniform on a spherical cap around ω (Dupuy & Benyoub
   * 2023, Listing 3): z uniform in [−ω.z, 1], azimuth uniform. Then unstretch
   * the sampled normal. */
  vec3 ws = v3(alpha * w.x, alpha * w.y, w.z);
  double len = v3_length(ws);
  if (!(len > 0.0)) return 0;
  ws = v3_scale(ws, 1.0 / len);
  double c = 1.0 + ws.z;
  double z = 1.0 - r2 * c;
  /* The disk point's direction scaled to the cap's radius sin θ: since
   * 1 − z² = r2 c (2 − r2 c), sin θ / √r2 = √(c (2 − r2 c)). */
  double k = sqrt(fmax(0.0, c * (2.0 - r2 * c)));
  vec3 h = v3(k * x + ws.x, k * y + ws.y, z + ws.z);
  vec3 mm = v3(alpha * h.x, alpha * h.y, fmax(0.0, h.z));
  double mlen = v3_length(mm);
  if (!(mlen > 0.0)) return 0;
  mm = v3_scale(mm, 1.0 / mlen);
  if (!(mm.z > 0.0)) return 0;
  *m = mm;
  return 1;
}

int brdf_ggx_sample_vndf(double alpha, vec3 w, double u1, double u2, vec3 *m) {
  double r = sqrt(u2), phi = 2.0 * M_PI * u1;
  return brdf_ggx_sample_vndf_disk(alpha, w, r * cos(phi), r * sin(phi), u2, m);
}
