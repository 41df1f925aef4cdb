/* Direction encodings (src/model/encoding.c). */
#include <math.h>
#include <string.h>

#include "core/rng.h"
#include "core/vec3.h"
#include "model/encoding.h"
#include "testing.h"

static void random_pair(core_rng *rng, float wi[3], float wo[3]) {
  vec3 a = v3_from_spherical(acos(core_rng_uniform(rng)), 2 * M_PI * core_rng_uniform(rng));
  vec3 b = v3_from_spherical(acos(core_rng_uniform(rng)), 2 * M_PI * core_rng_uniform(rng));
  wi[0] = (float)a.x, wi[1] = (float)a.y, wi[2] = (float)a.z;
  wo[0] = (float)b.x, wo[1] = (float)b.y, wo[2] = (float)b.z;
}

static void test_widths_and_names(void) {
  model_encoding e = {MODEL_ENCODING_CARTESIAN, 0};
  CHECK(model_encoding_width(&e) == 6);
  e.octaves = 3;
  CHECK(model_encoding_width(&e) == 42);
  model_encoding_kind k;
  CHECK(model_encoding_kind_parse("halfdiff", &k) && k == MODEL_ENCODING_HALFDIFF);
  CHECK(model_encoding_kind_parse("cartesian", &k) && k == MODEL_ENCODING_CARTESIAN);
  CHECK(!model_encoding_kind_parse("polar", &k));
  CHECK(!strcmp(model_encoding_kind_name(MODEL_ENCODING_HALFDIFF), "halfdiff"));
}

/* The BRDFs are isotropic and the decoders were trained with ωi in the xz-plane: every
 * encoding first rotates both directions so that ωi has azimuth 0. Rotating a pair about
 * the normal therefore leaves its features unchanged (it did not before: a renderer's
 * silhouettes decoded several times too bright), and a pair with ωi already in the
 * xz-plane (the training data) is encoded exactly as without the rotation. */
static void test_azimuth_invariance(void) {
  core_rng rng;
  core_rng_init(&rng, 11, 3);
  for (int kind = 0; kind < 2; kind++) {
    model_encoding e = {(model_encoding_kind)kind, 2};
    double worst = 0.0;
    for (int k = 0; k < 500; k++) {
      float wi[3], wo[3], ri[3], ro[3], a[30], b[30];
      random_pair(&rng, wi, wo);
      double t = 2 * M_PI * core_rng_uniform(&rng), c = cos(t), s = sin(t);
      ri[0] = (float)(c * wi[0] - s * wi[1]), ri[1] = (float)(s * wi[0] + c * wi[1]), ri[2] = wi[2];
      ro[0] = (float)(c * wo[0] - s * wo[1]), ro[1] = (float)(s * wo[0] + c * wo[1]), ro[2] = wo[2];
      model_encode(&e, 1, wi, wo, a, 30);
      model_encode(&e, 1, ri, ro, b, 30);
      for (int j = 0; j < 6; j++)
        worst = fmax(worst, fabs(a[j] - b[j]));
    }
    CHECK_MSG(worst < 1e-5, "%s: rotating both directions moves a feature by %g",
              model_encoding_kind_name(e.kind), worst);
  }
  /* ωi in the xz-plane with x > 0: features bit for bit those of the pair as given. */
  float wi[3] = {0.6f, 0.0f, 0.8f}, wo[3] = {-0.3f, 0.52f, 0.8f}, out[6];
  model_encoding cart = {MODEL_ENCODING_CARTESIAN, 0};
  model_encode(&cart, 1, wi, wo, out, 6);
  for (int j = 0; j < 3; j++)
    CHECK(out[j] == wi[j] && out[3 + j] == wo[j]);
  double a[3] = {0.6, 0.0, 0.8}, b[3] = {-0.3, 0.52, 0.8};
  model_encode_canonical(a, b);
  CHECK(a[0] == 0.6 && a[1] == 0.0 && b[0] == -0.3 && b[1] == 0.52);
}

static void test_cartesian_is_identity(void) {
  float wi[3] = {0.6f, 0.0f, 0.8f}, wo[3] = {0.0f, -0.6f, 0.8f}, out[8] = {0};
  model_encoding e = {MODEL_ENCODING_CARTESIAN, 0};
  model_encode(&e, 1, wi, wo, out, 8);
  for (int j = 0; j < 3; j++)
    CHECK(out[j] == wi[j] && out[3 + j] == wo[j]);
  CHECK(out[6] == 0.0f && out[7] == 0.0f); /* the stride's padding is left alone */
}

static void test_halfdiff_known_cases(void) {
  double h[3], d[3];
  /* Mirror pair about the normal: h = n, d = ωi. */
  double wi[3] = {sin(0.5), 0.0, cos(0.5)}, wo[3] = {-sin(0.5), 0.0, cos(0.5)};
  model_encode_halfdiff(wi, wo, h, d);
  CHECK_NEAR(h[0], 0.0, 1e-12);
  CHECK_NEAR(h[2], 1.0, 1e-12);
  for (int j = 0; j < 3; j++)
    CHECK_NEAR(d[j], wi[j], 1e-12);
  /* Retro-reflection: h = ωi = ωo, d = n (θd = 0). */
  double r[3] = {0.3, 0.4, sqrt(1 - 0.25)};
  model_encode_halfdiff(r, r, h, d);
  for (int j = 0; j < 3; j++)
    CHECK_NEAR(h[j], r[j], 1e-12);
  CHECK_NEAR(d[0], 0.0, 1e-12);
  CHECK_NEAR(d[1], 0.0, 1e-12);
  CHECK_NEAR(d[2], 1.0, 1e-12);
}

/* d is unit, d.z = cos θd = ωi·h, and d does not change when both directions
 * turn about the normal (isotropy). */
static void test_halfdiff_invariants(void) {
  core_rng rng;
  core_rng_init(&rng, 7, 0);
  for (int t = 0; t < 200; t++) {
    float fi[3], fo[3];
    random_pair(&rng, fi, fo);
    double wi[3] = {fi[0], fi[1], fi[2]}, wo[3] = {fo[0], fo[1], fo[2]}, h[3], d[3];
    model_encode_halfdiff(wi, wo, h, d);
    /* float inputs are unit only to ~1e-7 */
    CHECK_NEAR(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0, 1e-6);
    CHECK_NEAR(h[0] * h[0] + h[1] * h[1] + h[2] * h[2], 1.0, 1e-9);
    CHECK_NEAR(d[2], wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2], 1e-9);
    double phi = 2 * M_PI * core_rng_uniform(&rng), c = cos(phi), s = sin(phi);
    double ri[3] = {c * wi[0] - s * wi[1], s * wi[0] + c * wi[1], wi[2]};
    double ro[3] = {c * wo[0] - s * wo[1], s * wo[0] + c * wo[1], wo[2]};
    double h2[3], d2[3];
    model_encode_halfdiff(ri, ro, h2, d2);
    for (int j = 0; j < 3; j++)
      CHECK_NEAR(d2[j], d[j], 1e-9);
    CHECK_NEAR(h2[2], h[2], 1e-12);
  }
}

static void test_frequency_features(void) {
  float wi[3] = {0.0f, 0.6f, 0.8f}, wo[3] = {0.48f, 0.36f, 0.8f};
  model_encoding e = {MODEL_ENCODING_HALFDIFF, 2};
  float out[30];
  model_encode(&e, 1, wi, wo, out, 30);
  for (int o = 0; o < 2; o++) {
    for (int j = 0; j < 6; j++) {
      double x = out[j] * ldexp(M_PI, o);
      CHECK_NEAR(out[6 + 12 * o + 2 * j], sin(x), 1e-5);
      CHECK_NEAR(out[6 + 12 * o + 2 * j + 1], cos(x), 1e-5);
    }
  }
}

int main(void) {
  RUN(test_widths_and_names);
  RUN(test_cartesian_is_identity);
  RUN(test_azimuth_invariance);
  RUN(test_halfdiff_known_cases);
  RUN(test_halfdiff_invariants);
  RUN(test_frequency_features);
  return testing_finish();
}
