/* The energy penalty (src/model/energy.c): its gradient with respect to the
 * latents and the decoder weights against central finite differences, zero
 * below the ceilings, and ρ̂ equal to the albedo quadrature's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "model/albedo_quad.h"
#include "model/energy.h"
#include "testing.h"

enum { N = 3, D = 8 };

static double penalty_at(model_energy *e, const float *lat, const float *ceil, const float *lo) {
  double p = NAN;
  nbrdf_error err = {0};
  CHECK_OK(model_energy_add(e, N, lat, ceil, lo, 5, NULL, NULL, &p, NULL, &err), &err);
  return p;
}

/* A randomly initialised decoder of the small preset (NULL after a failed check). */
static model_decoder *small_decoder(unsigned seed) {
  nbrdf_error err = {0};
  model_decoder_config cfg;
  CHECK_OK(model_decoder_preset("small", D, &cfg, &err), &err);
  model_decoder *dec = NULL;
  CHECK_OK(model_decoder_create(&cfg, seed, &dec, &err), &err);
  return dec;
}

/* Latent entries whose gradient gl differs from central differences of the penalty
 * (bounds ceil and, may be NULL, lo). h = 1e-2 in float on O(1) inputs keeps the
 * decoder's round-off (~1e-7 relative) far below the curvature term. */
static int latent_mismatches(model_energy *e, float *lat, const float *ceil, const float *lo,
                             const float *gl) {
  const float h = 1e-2f;
  double gmax = 0.0;
  for (int k = 0; k < N * D; k++)
    gmax = fmax(gmax, fabs(gl[k]));
  CHECK(gmax > 0.0);
  int bad = 0;
  for (int k = 0; k < N * D; k++) {
    float keep = lat[k];
    lat[k] = keep + h;
    double up = penalty_at(e, lat, ceil, lo);
    lat[k] = keep - h;
    double down = penalty_at(e, lat, ceil, lo);
    lat[k] = keep;
    double num = (up - down) / (2.0 * h);
    if (fabs(num - gl[k]) > 0.03 * fabs(num) + 0.01 * gmax) {
      bad++;
      printf("latent %d: analytic %g numeric %g\n", k, gl[k], num);
    }
  }
  return bad;
}

/* A penalty of weight lambda (64 sampled directions) on a small random decoder, and N
 * latents amp · sin(freq k + phase); NULL *e after a failed check. */
static model_energy *penalty_setup(unsigned seed, float lambda, double amp, double freq,
                                   double phase, model_decoder **dec, float *lat) {
  nbrdf_error err = {0};
  *dec = small_decoder(seed);
  if (!*dec) return NULL;
  model_energy_options o = MODEL_ENERGY_OPTIONS_DEFAULT;
  o.lambda = lambda, o.samples = 64;
  model_energy *e = NULL;
  CHECK_OK(model_energy_create(*dec, &o, &e, &err), &err);
  for (int k = 0; k < N * D; k++)
    lat[k] = (float)(amp * sin(freq * k + phase));
  return e;
}

static void test_gradients(void) {
  nbrdf_error err = {0};
  model_energy_options o = MODEL_ENERGY_OPTIONS_DEFAULT;
  o.lambda = 2.0f, o.samples = 64;
  model_decoder *dec = NULL;
  float lat[N * D];
  model_energy *e = penalty_setup(11u, o.lambda, 1.5, 2.3, 0.4, &dec, lat);
  if (!e) {
    model_decoder_destroy(dec);
    return;
  }
  /* Ceilings: half of ρ̂ at even angles (active), twice ρ̂ at odd ones. */
  const int T = o.n_theta;
  double rho[N * MODEL_ENERGY_MAX_THETA];
  float ceil[N * MODEL_ENERGY_MAX_THETA];
  for (int k = 0; k < N * T; k++)
    ceil[k] = 1e9f;
  double p0;
  CHECK_OK(model_energy_add(e, N, lat, ceil, NULL, 5, NULL, NULL, &p0, rho, &err), &err);
  CHECK(p0 == 0.0);
  /* (An untrained decoder may output f = 0 everywhere for a latent: those
   * pairs stay inactive.) */
  int n_active = 0;
  for (int k = 0; k < N * T; k++) {
    CHECK(rho[k] >= 0.0 && isfinite(rho[k]));
    ceil[k] = (float)(k % 2 || rho[k] == 0.0 ? 2.0 * rho[k] + 1.0 : 0.5 * rho[k]);
    n_active += rho[k] > ceil[k];
  }
  CHECK(n_active >= 3);
  /* ρ̂ is the quadrature's sum of the decoded values. */
  {
    model_albedo_quad q;
    CHECK_OK(model_albedo_quad_init(&q, o.theta_deg[4] * M_PI / 180.0, o.samples,
                                    core_hash64(o.seed, 5), 0.0, &err),
             &err);
    model_runner run;
    CHECK_OK(model_runner_create(dec->nn, 64, NBRDF_NN_INFER, &run, &err), &err);
    float wi[64 * 3], wo[64 * 3], x[64 * D], f[64];
    double fd[64];
    for (int k = 0; k < 64; k++) {
      for (int a = 0; a < 3; a++)
        wi[3 * k + a] = (float)q.wi[a], wo[3 * k + a] = (float)q.wo[3 * k + a];
      memcpy(x + k * D, lat + 2 * D, D * sizeof *x);
    }
    CHECK_OK(model_decoder_eval(dec, &run, 64, 1, x, wi, wo, f, &err), &err);
    for (int k = 0; k < 64; k++)
      fd[k] = f[k];
    CHECK_REL(model_albedo_quad_sum(&q, fd, NULL), rho[2 * T + 4], 1e-5, 1e-9);
    model_runner_destroy(&run);
    model_albedo_quad_free(&q);
  }
  size_t np = nn_param_count(dec->nn);
  float *gl = calloc(N * D, sizeof *gl), *gw = calloc(np, sizeof *gw);
  double p;
  CHECK_OK(model_energy_add(e, N, lat, ceil, NULL, 5, gl, gw, &p, NULL, &err), &err);
  double expect = 0.0;
  for (int k = 0; k < N * T; k++)
    if (rho[k] > ceil[k]) expect += o.lambda * (rho[k] - ceil[k]) / (N * T);
  CHECK_REL(p, expect, 1e-6, 1e-12);
  CHECK(p > 0.0);
  CHECK(latent_mismatches(e, lat, ceil, NULL, gl) == 0);
  const float h = 1e-2f;
  int bad = 0;
  /* Weights: every 97th parameter. */
  float *w = nn_params(dec->nn);
  double wmax = 0.0;
  for (size_t k = 0; k < np; k++)
    wmax = fmax(wmax, fabs(gw[k]));
  CHECK(wmax > 0.0);
  bad = 0;
  for (size_t k = 0; k < np; k += 97) {
    float keep = w[k];
    w[k] = keep + h;
    double up = penalty_at(e, lat, ceil, NULL);
    w[k] = keep - h;
    double down = penalty_at(e, lat, ceil, NULL);
    w[k] = keep;
    double num = (up - down) / (2.0 * h);
    if (fabs(num - gw[k]) > 0.03 * fabs(num) + 0.01 * wmax) {
      bad++;
      printf("weight %zu: analytic %g numeric %g\n", k, gw[k], num);
    }
  }
  CHECK(bad == 0);
  free(gl), free(gw);
  model_energy_destroy(e);
  model_decoder_destroy(dec);
}

static void test_options(void) {
  nbrdf_error err = {0};
  model_energy_options o = MODEL_ENERGY_OPTIONS_DEFAULT;
  CHECK_OK(model_energy_parse_angles("0,60,89", "--energy-angles", &o, &err), &err);
  CHECK(o.n_theta == 3 && o.theta_deg[2] == 89.0);
  CHECK_FAILS(model_energy_parse_angles("0,90", "--energy-angles", &o, &err), NBRDF_ERR_ARGUMENT,
              &err, "--energy-angles");
  CHECK_FAILS(model_energy_parse_angles("x", "--energy-angles", &o, &err), NBRDF_ERR_ARGUMENT, &err,
              "not an angle");
}

/* The polar rule (polar_rings > 0): ρ̂ is the audit's measurement (model_albedo_decoded_polar)
 * whatever the step, and a rule too small is refused. */
static void test_polar(void) {
  nbrdf_error err = {0};
  model_decoder *dec = small_decoder(12u);
  if (!dec) return;
  model_energy_options o = MODEL_ENERGY_OPTIONS_DEFAULT;
  o.lambda = 1.0f, o.polar_rings = 12, o.polar_phi = 8, o.samples = 0; /* samples unused */
  model_energy *e = NULL;
  CHECK_OK(model_energy_create(dec, &o, &e, &err), &err);
  float lat[N * D];
  for (int k = 0; k < N * D; k++)
    lat[k] = (float)(1.2 * cos(1.9 * k + 0.2));
  float ceil[N * MODEL_ENERGY_MAX_THETA];
  for (int k = 0; k < N * MODEL_ENERGY_MAX_THETA; k++)
    ceil[k] = 1e9f;
  double a[N * MODEL_ENERGY_MAX_THETA], b[N * MODEL_ENERGY_MAX_THETA],
      want[N * MODEL_ENERGY_MAX_THETA];
  if (e) {
    CHECK_OK(model_energy_add(e, N, lat, ceil, NULL, 1, NULL, NULL, NULL, a, &err), &err);
    CHECK_OK(model_energy_add(e, N, lat, ceil, NULL, 7, NULL, NULL, NULL, b, &err), &err);
    model_runner run;
    CHECK_OK(model_runner_create(dec->nn, 4096, NBRDF_NN_INFER, &run, &err), &err);
    CHECK_OK(model_albedo_decoded_polar(dec, &run, N, lat, o.n_theta, o.theta_deg, 12, 8, want,
                                        &err),
             &err);
    model_runner_destroy(&run);
    int some = 0;
    for (int k = 0; k < N * o.n_theta; k++) {
      CHECK(a[k] == b[k]);
      CHECK_REL(a[k], want[k], 1e-5, 1e-9);
      some |= want[k] > 0.0;
    }
    CHECK(some);
  }
  model_energy_destroy(e);
  o.polar_rings = 2;
  CHECK_FAILS(model_energy_create(dec, &o, &e, &err), NBRDF_ERR_ARGUMENT, &err, "polar rule");
  model_decoder_destroy(dec);
}

/* The floor (issue 35: a smooth coat over a mirror decoded too little light): below it the
 * penalty is λ · (floor − ρ̂), its latent gradient the central differences', and the same
 * latents between their bounds give no penalty. */
static void test_floor(void) {
  nbrdf_error err = {0};
  model_energy_options o = MODEL_ENERGY_OPTIONS_DEFAULT;
  o.lambda = 1.5f, o.samples = 64;
  model_decoder *dec = NULL;
  float lat[N * D];
  model_energy *e = penalty_setup(17u, o.lambda, 1.2, 1.7, 1.77, &dec, lat);
  if (!e) {
    model_decoder_destroy(dec);
    return;
  }
  const int T = o.n_theta;
  double rho[N * MODEL_ENERGY_MAX_THETA];
  float ceil[N * MODEL_ENERGY_MAX_THETA], lo[N * MODEL_ENERGY_MAX_THETA];
  for (int k = 0; k < N * T; k++)
    ceil[k] = 1e9f, lo[k] = 0.0f;
  double p;
  CHECK_OK(model_energy_add(e, N, lat, ceil, lo, 5, NULL, NULL, &p, rho, &err), &err);
  CHECK(p == 0.0);
  /* Floors: twice ρ̂ + 0.1 at even entries (below: active), half of ρ̂ at odd ones. */
  double expect = 0.0;
  for (int k = 0; k < N * T; k++) {
    lo[k] = (float)(k % 2 ? 0.5 * rho[k] : 2.0 * rho[k] + 0.1);
    if (rho[k] < lo[k]) expect += o.lambda * (lo[k] - rho[k]) / (N * T);
  }
  float *gl = calloc(N * D, sizeof *gl);
  CHECK_OK(model_energy_add(e, N, lat, ceil, lo, 5, gl, NULL, &p, NULL, &err), &err);
  CHECK(p > 0.0);
  CHECK_REL(p, expect, 1e-6, 1e-12);
  CHECK(latent_mismatches(e, lat, ceil, lo, gl) == 0);
  /* Without floors the same call has nothing to penalise. */
  CHECK(penalty_at(e, lat, ceil, NULL) == 0.0);
  free(gl);
  model_energy_destroy(e);
  model_decoder_destroy(dec);
}

int main(void) {
  RUN(test_gradients);
  RUN(test_floor);
  RUN(test_polar);
  RUN(test_options);
  return testing_finish();
}
