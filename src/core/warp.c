#include "core/warp.h"

void core_warp_disk(double u1, double u2, double *x, double *y) {
  double a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
  if (a == 0.0 && b == 0.0) {
    *x = *y = 0.0;
    return;
  }
  double r, phi;
  if (fabs(a) > fabs(b)) {
    r = a;
    phi = (M_PI / 4.0) * (b / a);
  } else {
    r = b;
    phi = M_PI / 2.0 - (M_PI / 4.0) * (a / b);
  }
  *x = r * cos(phi);
  *y = r * sin(phi);
}

vec3 core_warp_cosine_hemisphere(double u1, double u2) {
  double x, y;
  core_warp_disk(u1, u2, &x, &y);
  double z = sqrt(fmax(0.0, 1.0 - x * x - y * y));
  return v3(x, y, z);
}

double core_warp_cosine_hemisphere_pdf(vec3 w) { return w.z > 0.0 ? w.z / M_PI : 0.0; }

vec3 core_warp_uniform_sphere(double u1, double u2) {
  double z = 1.0 - 2.0 * u1;
  double r = sqrt(fmax(0.0, 1.0 - z * z));
  double phi = 2.0 * M_PI * u2;
  return v3(r * cos(phi), r * sin(phi), z);
}

vec3 core_warp_uniform_hemisphere(double u1, double u2) {
  double z = u1;
  double r = sqrt(fmax(0.0, 1.0 - z * z));
  double phi = 2.0 * M_PI * u2;
  return v3(r * cos(phi), r * sin(phi), z);
}
