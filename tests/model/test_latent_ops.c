/* Latent interpolation and the bilinear base-latent tables. */
#include <math.h>
#include <string.h>

#include "core/rng.h"
#include "model/base_table.h"
#include "model/layering.h"
#include "nbrdf/model.h"
#include "testing.h"

static void test_interpolate(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  float l[3 * 4] = {1, 2, 3, 4, -1, 0, 1, 2, 10, 20, 30, 40}, out[4], out2[4];
  double w[3] = {0.5, 0.25, 0.25};
  CHECK_OK(nbrdf_latent_interpolate(3, 4, l, w, out, err), err);
  for (int j = 0; j < 4; j++)
    CHECK_NEAR(out[j], 0.5 * l[j] + 0.25 * l[4 + j] + 0.25 * l[8 + j], 1e-6);
  /* Weights need not sum to 1: they are normalised. */
  double w4[3] = {2.0, 1.0, 1.0};
  CHECK_OK(nbrdf_latent_interpolate(3, 4, l, w4, out2, err), err);
  for (int j = 0; j < 4; j++)
    CHECK(out2[j] == out[j]);
  /* Identical latents come back bit for bit, whatever the weights. */
  core_rng rng;
  core_rng_init(&rng, 3, 0);
  float same[5 * 32], avg[32];
  for (int j = 0; j < 32; j++)
    same[j] = (float)core_rng_normal(&rng);
  for (int k = 1; k < 5; k++)
    memcpy(same + 32 * k, same, 32 * sizeof(float));
  double ww[5] = {0.1, 0.3, 0.05, 0.35, 0.2};
  CHECK_OK(nbrdf_latent_interpolate(5, 32, same, ww, avg, err), err);
  CHECK(!memcmp(avg, same, sizeof avg));
  /* A single weight selects its latent. */
  double one[3] = {0.0, 1.0, 0.0};
  CHECK_OK(nbrdf_latent_interpolate(3, 4, l, one, out, err), err);
  CHECK(!memcmp(out, l + 4, sizeof out));
  /* Refusals. */
  double bad[3] = {0.5, NAN, 0.5}, neg[3] = {1.0, -0.5, 0.5}, zero[3] = {0, 0, 0};
  CHECK_FAILS(nbrdf_latent_interpolate(3, 4, l, bad, out, err), NBRDF_ERR_ARGUMENT, err,
              "weight 1");
  CHECK_FAILS(nbrdf_latent_interpolate(3, 4, l, neg, out, err), NBRDF_ERR_ARGUMENT, err,
              "weight 1");
  CHECK_FAILS(nbrdf_latent_interpolate(3, 4, l, zero, out, err), NBRDF_ERR_ARGUMENT, err, "sum");
  CHECK_FAILS(nbrdf_latent_interpolate(0, 4, l, w, out, err), NBRDF_ERR_ARGUMENT, err, "0 latents");
}

static void test_table_lookup(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  const float alpha[4] = {0.01f, 0.1f, 0.4f, 1.0f}, eta[3] = {1.05f, 1.5f, 2.0f};
  model_base_table t;
  CHECK_OK(model_base_table_init(&t, MODEL_TABLE_DIELECTRIC, 3, 4, alpha, 3, eta, err), err);
  core_rng rng;
  core_rng_init(&rng, 4, 0);
  for (int i = 0; i < 4 * 3 * 3; i++)
    t.latents[i] = (float)core_rng_normal(&rng);
  /* Exact at every grid node. */
  for (int a = 0; a < 4; a++) {
    for (int b = 0; b < 3; b++) {
      double p0 = alpha[a], p1 = eta[b];
      float out[3];
      unsigned char flag = 9;
      CHECK_OK(model_base_table_lookup(&t, 1, &p0, &p1, 1, out, &flag, err), err);
      CHECK(!memcmp(out, t.latents + (a * 3 + b) * 3, sizeof out));
      CHECK(flag == 0);
    }
  }
  /* Bilinear inside a cell (linear in the axis values). */
  double p0 = 0.1 + 0.25 * 0.3, p1 = 1.5 + 0.5 * 0.5;
  float out[3];
  CHECK_OK(model_base_table_lookup(&t, 1, &p0, &p1, 1, out, NULL, err), err);
  for (int j = 0; j < 3; j++) {
    const float *z = t.latents;
    double expect = 0.75 * 0.5 * z[(1 * 3 + 1) * 3 + j] + 0.75 * 0.5 * z[(1 * 3 + 2) * 3 + j] +
                    0.25 * 0.5 * z[(2 * 3 + 1) * 3 + j] + 0.25 * 0.5 * z[(2 * 3 + 2) * 3 + j];
    CHECK_NEAR(out[j], expect, 1e-5);
  }
  /* Out of the grid: clamped and flagged, or refused; NaN always refused. */
  /* Query 0 = (0.001, 3.0): both outside; query 1 = (0.4, 1.5): inside. */
  double lo[2] = {0.001, 0.4}, hi[2] = {3.0, 1.5};
  float two[6];
  unsigned char flags[2];
  CHECK_OK(model_base_table_lookup(&t, 2, lo, hi, 0, two, flags, err), err);
  CHECK(flags[0] == (NBRDF_CLAMPED_PARAM0 | NBRDF_CLAMPED_PARAM1));
  CHECK(flags[1] == 0);
  CHECK(!memcmp(two, t.latents + (0 * 3 + 2) * 3, 3 * sizeof(float))); /* (0.01, 2.0) */
  CHECK_FAILS(model_base_table_lookup(&t, 2, lo, hi, 1, two, flags, err), NBRDF_ERR_ARGUMENT, err,
              "alpha1 = 0.001 (query 0) is outside");
  double nan_p = NAN, ok_p = 1.5;
  CHECK_FAILS(model_base_table_lookup(&t, 1, &nan_p, &ok_p, 0, two, flags, err), NBRDF_ERR_ARGUMENT,
              err, "alpha1 = nan");
  /* Axes must increase strictly. */
  model_base_table bad;
  const float flat[3] = {1.0f, 1.0f, 2.0f};
  CHECK_FAILS(model_base_table_init(&bad, MODEL_TABLE_CONDUCTOR, 3, 4, alpha, 3, flat, err),
              NBRDF_ERR_ARGUMENT, err, "r0 axis");
  model_base_table_free(&t);
}

/* The layering presets cost what model/layering.h and the model card say. */
static void test_layering_presets(void) {
  nbrdf_error err;
  const char *names[] = {"paper", "medium", "small"};
  const int64_t macs[] = {1098752, 221696, 45312};
  for (int i = 0; i < 3; i++) {
    nn_spec spec;
    CHECK_OK(model_layering_spec(names[i], 32, &spec, &err), &err);
    CHECK_MSG(nn_spec_macs(&spec) == macs[i], "%s: %lld MACs", names[i],
              (long long)nn_spec_macs(&spec));
    CHECK(!strcmp(model_layering_presets[i], names[i]));
  }
  nn_spec spec;
  CHECK(model_layering_spec("huge", 32, &spec, &err) == NBRDF_ERR_ARGUMENT);
}

int main(void) {
  RUN(test_layering_presets);
  RUN(test_interpolate);
  RUN(test_table_lookup);
  return testing_finish();
}
