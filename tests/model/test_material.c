/* model/material.h: the layered material's names, conventions, clamping and its
 * ground truth. No network is involved: values and Monte Carlo results (per-query
 * streams) are compared exactly. */
#include <math.h>
#include <string.h>

#include "model/material.h"
#include "testing.h"

static void test_names_and_conventions(void) {
  CHECK(!strcmp(model_material_param_name(NBRDF_BAKE_ALPHA1), "alpha1"));
  CHECK(!strcmp(model_material_param_name(NBRDF_BAKE_SIGMA_T), "sigma_t"));
  CHECK(!strcmp(model_material_param_name(NBRDF_BAKE_PARAM_COUNT), "parameter"));
  CHECK(model_roughness_parse("perceptual") == NBRDF_ROUGHNESS_PERCEPTUAL);
  CHECK(model_roughness_parse("alpha") == NBRDF_ROUGHNESS_ALPHA);
  CHECK(model_roughness_parse("Alpha") == -1);
  /* -0 -> +0 (equal tuples, equal bytes); r -> r^2 for the two roughnesses only. */
  float z = model_material_read(NBRDF_BAKE_ETA, NBRDF_ROUGHNESS_ALPHA, -0.0f);
  CHECK(z == 0.0f && !signbit(z));
  CHECK(model_material_read(NBRDF_BAKE_ALPHA2, NBRDF_ROUGHNESS_PERCEPTUAL, 0.3f) == 0.3f * 0.3f);
  CHECK(model_material_read(NBRDF_BAKE_R0, NBRDF_ROUGHNESS_PERCEPTUAL, 0.3f) == 0.3f);
}

static void test_clamp_ranges(void) {
  float p[MODEL_MATERIAL_PARAMS] = {0.0f, 0.5f, 2.0f, 1.5f, -1.0f, 2000.0f};
  float q[MODEL_MATERIAL_PARAMS];
  memcpy(q, p, sizeof p);
  CHECK(model_material_clamp(MODEL_RANGE_NONE, NULL, NULL, q) == 0);
  CHECK(!memcmp(p, q, sizeof p));
  CHECK(model_material_clamp(MODEL_RANGE_TRUTH, NULL, NULL, q) == 6);
  CHECK(q[NBRDF_BAKE_ALPHA1] == (float)NBRDF_GT_ALPHA_MIN);
  CHECK(q[NBRDF_BAKE_ETA] == (float)NBRDF_GT_ETA_MIN);
  CHECK(q[NBRDF_BAKE_ALPHA2] == (float)NBRDF_GT_ALPHA_MAX);
  CHECK(q[NBRDF_BAKE_R0] == 1.0f && q[NBRDF_BAKE_ALBEDO] == 0.0f);
  CHECK(q[NBRDF_BAKE_SIGMA_T] == (float)NBRDF_GT_SIGMA_T_MAX);
  const float lo[MODEL_MATERIAL_PARAMS] = {0.01f, 1.05f, 0.01f, 0.0f, 0.0f, 0.0f};
  const float hi[MODEL_MATERIAL_PARAMS] = {1.0f, 2.0f, 1.0f, 1.0f, 1.0f, NBRDF_BAKE_SIGMA_T_MAX};
  memcpy(q, p, sizeof p);
  CHECK(model_material_clamp(MODEL_RANGE_TRAINED, lo, hi, q) == 6);
  for (int i = 0; i < MODEL_MATERIAL_PARAMS; i++)
    CHECK(q[i] >= lo[i] && q[i] <= hi[i]);
  /* Inside: unchanged, bit for bit. */
  float in[MODEL_MATERIAL_PARAMS] = {0.2f, 1.5f, 0.3f, 0.9f, 0.8f, 1.0f};
  memcpy(q, in, sizeof in);
  CHECK(model_material_clamp(MODEL_RANGE_TRUTH, NULL, NULL, q) == 0);
  CHECK(model_material_clamp(MODEL_RANGE_TRAINED, lo, hi, q) == 0);
  CHECK(!memcmp(in, q, sizeof in));
}

static void test_truth_is_the_layered_brdf(void) {
  const double p[MODEL_MATERIAL_PARAMS] = {0.2, 1.5, 0.3, 0.9, 0.8, 1.0};
  nbrdf_error err = {0};
  nbrdf_brdf *m = NULL, *bottom = NULL, *direct = NULL;
  CHECK_OK(model_material_truth(p, &m, &err), &err);
  CHECK_OK(nbrdf_brdf_create_conductor(0.3, 0.9, &bottom, &err), &err);
  CHECK_OK(nbrdf_brdf_create_layered(0.2, 1.5, 0.8, 1.0, bottom, &direct, &err), &err);
  nbrdf_query q = {{0.3, 0.0, sqrt(1.0 - 0.09)}, {-0.2, 0.1, sqrt(1.0 - 0.05)}};
  nbrdf_eval_options o = NBRDF_EVAL_OPTIONS_DEFAULT;
  double fa, fb, sa, sb;
  CHECK_OK(nbrdf_brdf_eval(m, 1, &q, &o, &fa, &sa, &err), &err);
  CHECK_OK(nbrdf_brdf_eval(direct, 1, &q, &o, &fb, &sb, &err), &err);
  CHECK(fa == fb && sa == sb);
  nbrdf_brdf_destroy(m), nbrdf_brdf_destroy(direct), nbrdf_brdf_destroy(bottom);
  /* Values as given: the ground truth refuses what it cannot represent. */
  const double bad[MODEL_MATERIAL_PARAMS] = {0.2, 0.5, 0.3, 0.9, 0.8, 1.0};
  CHECK_FAILS(model_material_truth(bad, &m, &err), NBRDF_ERR_ARGUMENT, &err, "eta");
}

/* unnormalise inverts normalise in each parameter's warped scale (sqrt for alpha, log1p for
 * sigma_t), ends exact to float rounding. */
static void test_normalise_round_trip(void) {
  const float lo[MODEL_MATERIAL_PARAMS] = {0.01f, 1.05f, 0.01f, 0.0f, 0.0f, 0.0f};
  const float hi[MODEL_MATERIAL_PARAMS] = {1.0f, 2.0f, 1.0f, 1.0f, 1.0f, NBRDF_BAKE_SIGMA_T_MAX};
  for (int id = 0; id < MODEL_MATERIAL_PARAMS; id++) {
    for (int k = 0; k <= 8; k++) {
      double u = k / 8.0;
      float v = model_material_unnormalise(lo, hi, id, u);
      CHECK_MSG(v >= lo[id] - 1e-6f * (1 + hi[id]) && v <= hi[id] * (1 + 1e-6f),
                "param %d u %g: %g outside [%g, %g]", id, u, v, lo[id], hi[id]);
      CHECK_NEAR(model_material_normalise(lo, hi, id, v), u, 1e-5);
    }
  }
  /* The warp is not linear: alpha's midpoint in the normalised scale is below the mean. */
  CHECK(model_material_unnormalise(lo, hi, NBRDF_BAKE_ALPHA1, 0.5) < 0.5f * (lo[0] + hi[0]));
}

int main(void) {
  RUN(test_names_and_conventions);
  RUN(test_clamp_ranges);
  RUN(test_truth_is_the_layered_brdf);
  RUN(test_normalise_round_trip);
  return testing_finish();
}
