#include "model/encoding.h"

#include <math.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

int model_encoding_width(const model_encoding *enc) { return 6 + 12 * enc->octaves; }

const char *model_encoding_kind_name(model_encoding_kind kind) {
  switch (kind) {
  case MODEL_ENCODING_CARTESIAN:
    return "cartesian";
  case MODEL_ENCODING_HALFDIFF:
    return "halfdiff";
  }
  return NULL;
}

int model_encoding_kind_parse(const char *name, model_encoding_kind *kind) {
  if (!strcmp(name, "cartesian")) {
    *kind = MODEL_ENCODING_CARTESIAN;
    return 1;
  }
  if (!strcmp(name, "halfdiff")) {
    *kind = MODEL_ENCODING_HALFDIFF;
    return 1;
  }
  return 0;
}

void model_encode_halfdiff(const double wi[3], const double wo[3], double h[3], double d[3]) {
  double hx = wi[0] + wo[0], hy = wi[1] + wo[1], hz = wi[2] + wo[2];
  double len = sqrt(hx * hx + hy * hy + hz * hz);
  /* ωi = −ωo only happens at the horizon; any h is then as good as another. */
  if (!(len > 1e-12)) {
    hx = 0.0, hy = 0.0, hz = 1.0;
  } else {
    hx /= len, hy /= len, hz /= len;
  }
  h[0] = hx, h[1] = hy, h[2] = hz;
  /* Rotate ωi by −φh about z, then by −θh about y (Rusinkiewicz 1998). */
  double sin_theta = sqrt(hx * hx + hy * hy);
  double cos_phi = 1.0, sin_phi = 0.0;
  if (sin_theta > 1e-12) cos_phi = hx / sin_theta, sin_phi = hy / sin_theta;
  double x1 = cos_phi * wi[0] + sin_phi * wi[1];
  double y1 = -sin_phi * wi[0] + cos_phi * wi[1];
  double z1 = wi[2];
  d[0] = hz * x1 - sin_theta * z1;
  d[1] = y1;
  d[2] = sin_theta * x1 + hz * z1;
}

void model_encode_canonical(double wi[3], double wo[3]) {
  double s = sqrt(wi[0] * wi[0] + wi[1] * wi[1]);
  if (!(s > 1e-12)) return; /* ωi at the normal: every azimuth is its own */
  double c = wi[0] / s, sn = wi[1] / s, x = wo[0], y = wo[1];
  /* ωi itself lands on (s, 0, z) exactly (sqrt(x²) = |x| in IEEE arithmetic,
   * so the training data's ωi stay as they are). */
  wi[0] = s, wi[1] = 0.0;
  wo[0] = c * x + sn * y, wo[1] = -sn * x + c * y;
}

void model_encode(const model_encoding *enc, size_t n, const float *wi, const float *wo, float *out,
                  size_t stride) {
  for (size_t k = 0; k < n; k++) {
    double a[3] = {wi[3 * k], wi[3 * k + 1], wi[3 * k + 2]};
    double b[3] = {wo[3 * k], wo[3 * k + 1], wo[3 * k + 2]};
    model_encode_canonical(a, b);
    double base[6];
    if (enc->kind == MODEL_ENCODING_HALFDIFF) {
      model_encode_halfdiff(a, b, base, base + 3);
    } else {
      memcpy(base, a, sizeof a);
      memcpy(base + 3, b, sizeof b);
    }
    float *row = out + k * stride;
    for (int j = 0; j < 6; j++)
      row[j] = (float)base[j];
    float *freq = row + 6;
    for (int o = 0; o < enc->octaves; o++) {
      double scale = ldexp(M_PI, o);
      for (int j = 0; j < 6; j++) {
        freq[12 * o + 2 * j] = (float)sin(scale * base[j]);
        freq[12 * o + 2 * j + 1] = (float)cos(scale * base[j]);
      }
    }
  }
}
