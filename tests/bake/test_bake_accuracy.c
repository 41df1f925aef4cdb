/* The accuracy levels of a bake (issue 17): the plan within a budget
 * (deterministic, refusing a budget too small with what would fit), the
 * selection of representative tuples (deterministic for a seed, all of them
 * when few), the carried correction (exact at fitted tuples, fading far from
 * them), a tiny constant bake at the fitted level whose held-out error is
 * below the fast level's on the same BRDF (a sharp low-IOR coat, where the
 * universal networks are poor), the header attribute, and cancel during the
 * fit leaving no file. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bake/bake_accuracy.h"
#include "bake/bake_select.h"
#include "nbrdf/bake.h"
#include "testing.h"
#include "texture/latent_exr.h"

static nbrdf_model *model;

static void test_plan(void) {
  nbrdf_error e, *err = &e;
  int64_t macs = nbrdf_model_decoder_macs(model);
  bake_plan a, b, big;
  CHECK_OK(bake_plan_make(NBRDF_BAKE_FITTED, 120.0, 5000, macs, 0, &a, err), err);
  CHECK_OK(bake_plan_make(NBRDF_BAKE_FITTED, 120.0, 5000, macs, 0, &b, err), err);
  CHECK(!memcmp(&a, &b, sizeof a)); /* a pure function of its inputs */
  CHECK(a.n_fit >= 1 && a.n_held >= 1 && a.project_steps >= 100 && a.joint_steps == 0);
  CHECK_MSG(a.cost <= 120.0 * 1.01, "plan costs %g s for a budget of 120", a.cost);
  CHECK_OK(bake_plan_make(NBRDF_BAKE_FITTED, 600.0, 5000, macs, 0, &big, err), err);
  CHECK(big.n_fit > a.n_fit);
  /* A constant (one tuple): everything on it, more incident directions. */
  CHECK_OK(bake_plan_make(NBRDF_BAKE_SPECIALISED, 60.0, 1, macs, 0, &a, err), err);
  CHECK(a.n_fit == 1 && a.incident == 32 && a.joint_steps > 0);
  /* Too small: refused, saying what it needs and what would fit. */
  CHECK_FAILS(bake_plan_make(NBRDF_BAKE_FITTED, 0.5, 10, macs, 0, &a, err), NBRDF_ERR_ARGUMENT, err,
              "too small for 'fitted'");
  CHECK(strstr(e.message, "or use 'fast'") != NULL);
  CHECK_FAILS(bake_plan_make(NBRDF_BAKE_SPECIALISED, 1.2, 10, macs, 0, &a, err), NBRDF_ERR_ARGUMENT,
              err, "'fitted' fits");
}

static void test_select(void) {
  nbrdf_error e, *err = &e;
  float lo[NBRDF_BAKE_PARAM_COUNT], hi[NBRDF_BAKE_PARAM_COUNT];
  model_material_ranges(model, lo, hi);
  enum { N = 500 };
  bake_tuple *t = malloc(sizeof *t * N);
  for (int i = 0; i < N; i++) {
    float u = (float)((i * 37) % N) / N, v = (float)((i * 101) % N) / N;
    bake_tuple x = {{0.02f + 0.9f * u, 1.1f + 0.8f * v, 0.3f, 0.5f + 0.4f * u * v, 0.8f, 1.0f}};
    t[i] = x;
  }
  bake_selection a, b, c;
  CHECK_OK(bake_select(t, N, lo, hi, 20, 8, 7, &a, err), err);
  CHECK_OK(bake_select(t, N, lo, hi, 20, 8, 7, &b, err), err);
  CHECK_OK(bake_select(t, N, lo, hi, 20, 8, 8, &c, err), err);
  CHECK(a.n_fit == 20 && a.n_held == 8 && !a.held_are_fitted);
  CHECK(!memcmp(a.fit, b.fit, sizeof *a.fit * 20) && !memcmp(a.held, b.held, sizeof *a.held * 8));
  CHECK(memcmp(a.held, c.held, sizeof *a.held * 8) != 0); /* the seed matters */
  /* Held-out tuples are never fitted ones. */
  for (size_t i = 0; i < a.n_held; i++)
    for (size_t j = 0; j < a.n_fit; j++)
      CHECK(memcmp(&a.held[i], &a.fit[j], sizeof a.held[i]) != 0);
  /* Farthest-point picks spread out: no two fitted tuples nearly equal. */
  float closest = 1e30f;
  for (size_t i = 0; i < a.n_fit; i++)
    for (size_t j = i + 1; j < a.n_fit; j++) {
      float d = bake_tuple_distance2(&a.fit[i], &a.fit[j], lo, hi);
      if (d < closest) closest = d;
    }
  CHECK_MSG(closest > 0.01f, "two fitted tuples %g apart", sqrt(closest));
  bake_selection_free(&a), bake_selection_free(&b), bake_selection_free(&c);
  /* Few tuples: all fitted, the held-out set repeats them. */
  CHECK_OK(bake_select(t, 3, lo, hi, 20, 8, 7, &a, err), err);
  CHECK(a.n_fit == 3 && a.held_are_fitted && a.n_held == 3);
  bake_selection_free(&a);
  free(t);
}

/* Per-tuple random streams: the ground truth is the same for 1 and 2 threads. */
static void test_truth_threads(void) {
  nbrdf_error e, *err = &e;
  bake_tuple t[3] = {{{0.05f, 1.3f, 0.2f, 0.9f, 0.7f, 1.0f}},
                     {{0.4f, 1.6f, 0.5f, 0.3f, 0.9f, 2.0f}},
                     {{0.02f, 1.1f, 0.3f, 0.95f, 1.0f, 0.0f}}};
  bake_truth_settings s = {2, 8, 4, 16, 8, 8, 42, NULL, 0.0, 3.0, NULL};
  train_samples a = {0}, b = {0};
  double la[3 * BAKE_LOBE_N_THETA * 64], lb[3 * BAKE_LOBE_N_THETA * 64];
  omp_set_num_threads(1);
  CHECK_OK(bake_truth_samples(t, 3, &s, &a, err), err);
  CHECK_OK(bake_truth_lobes(t, 3, &s, la, err), err);
  omp_set_num_threads(2);
  CHECK_OK(bake_truth_samples(t, 3, &s, &b, err), err);
  CHECK_OK(bake_truth_lobes(t, 3, &s, lb, err), err);
  CHECK(a.n_rows == 3 * 2 * 8 && b.n_rows == a.n_rows);
  if (a.n_rows == b.n_rows && a.n_rows) {
    CHECK(!memcmp(a.f, b.f, sizeof(float) * a.n_rows));
    CHECK(!memcmp(a.wo, b.wo, sizeof(float) * 3 * a.n_rows));
  }
  CHECK(!memcmp(la, lb, sizeof la));
  double sum = 0.0;
  for (size_t i = 0; i < a.n_rows; i++)
    sum += a.f[i];
  CHECK(sum > 0.0 && isfinite(sum));
  train_samples_free(&a), train_samples_free(&b);
}

static void test_correction(void) {
  enum { D = 32 };
  bake_correction c = {0};
  model_material_ranges(model, c.lo, c.hi);
  c.latent_dim = D;
  c.n = 2;
  bake_tuple fitted[2] = {{{0.1f, 1.5f, 0.3f, 0.8f, 0.5f, 1.0f}},
                          {{0.5f, 1.5f, 0.3f, 0.8f, 0.5f, 1.0f}}};
  float delta[2 * D];
  for (int d = 0; d < D; d++)
    delta[d] = 1.0f, delta[D + d] = -1.0f;
  c.tuples = fitted, c.delta = delta, c.radius = 0.1f;
  bake_tuple q[3] = {fitted[0], fitted[1], {{0.01f, 2.0f, 1.0f, 0.0f, 0.0f, 5.0f}}};
  float z[3 * D] = {0};
  bake_correct_latents(&c, q, NULL, 3, z, D);
  CHECK(z[0] == 1.0f && z[D - 1] == 1.0f);   /* exactly the fitted correction */
  CHECK(z[D] == -1.0f && z[2 * D - 1] == -1.0f);
  CHECK_MSG(fabsf(z[2 * D]) < 1e-3f, "far tuple moved by %g", z[2 * D]); /* faded out */
}

static nbrdf_bake_inputs sharp_coat(void) {
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  const float v[NBRDF_BAKE_PARAM_COUNT] = {0.01f, 1.05f, 0.5f, 0.95f, 1.0f, 0.0f};
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    nbrdf_bake_param_constant(&in.param[id], v[id]);
  return in;
}

static void test_fitted_constant(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = sharp_coat();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.accuracy = NBRDF_BAKE_FITTED;
  o.budget = 12.0;
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(model, &in, &o, testing_path("fitted.exr"), &rep, err), err);
  CHECK(rep.accuracy == NBRDF_BAKE_FITTED && rep.fitted_tuples == 1 && rep.heldout_tuples == 1);
  CHECK(rep.distinct == 1 && rep.budget == 12.0);
  CHECK_MSG(rep.heldout_error < 0.85 * rep.heldout_error_fast,
            "held-out lobe error fitted %.4f vs fast %.4f", rep.heldout_error,
            rep.heldout_error_fast);
  printf("  sharp low-IOR coat: held-out lobe error fast %.2f %%, fitted %.2f %%\n",
         100 * rep.heldout_error_fast, 100 * rep.heldout_error);
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, testing_path("fitted.exr"), err), err);
  if (r) {
    const char *acc = texture_latent_reader_info(r)->accuracy;
    CHECK_MSG(strstr(acc, "level=fitted; budget=12;") && strstr(acc, "fitted=1; heldout=1"),
              "accuracy attribute '%s'", acc);
    texture_latent_reader_close(r);
  }
  /* A fast bake writes no such attribute. */
  o = (nbrdf_bake_options)NBRDF_BAKE_OPTIONS_DEFAULT;
  CHECK_OK(nbrdf_bake(model, &in, &o, testing_path("fast.exr"), &rep, err), err);
  CHECK(rep.accuracy == NBRDF_BAKE_FAST && rep.fitted_tuples == 0);
  CHECK_OK(texture_latent_reader_open(&r, testing_path("fast.exr"), err), err);
  if (r) {
    CHECK(texture_latent_reader_info(r)->accuracy[0] == 0);
    texture_latent_reader_close(r);
  }
}

/* SPECIALISED: the fine-tuned decoder goes into the texture (format 2), the
 * held-out error is below the fast level's, and the texture decodes with its
 * own decoder: nbrdf_model_for_texture's model gives the held-out tuple's
 * values, the bundle's decoder (ignoring the embedded one) does not. */
static void test_specialised_constant(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = sharp_coat();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.accuracy = NBRDF_BAKE_SPECIALISED;
  o.budget = 4.0;
  o.mip_levels = 1;
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(model, &in, &o, testing_path("spec.exr"), &rep, err), err);
  CHECK(rep.accuracy == NBRDF_BAKE_SPECIALISED && rep.fitted_tuples == 1);
  CHECK_MSG(rep.heldout_error < 0.5 * rep.heldout_error_fast,
            "held-out lobe error specialised %.4f vs fast %.4f", rep.heldout_error,
            rep.heldout_error_fast);
  printf("  sharp low-IOR coat: held-out lobe error fast %.2f %%, specialised %.2f %%\n",
         100 * rep.heldout_error_fast, 100 * rep.heldout_error);
  nbrdf_decoder_info info;
  CHECK_OK(nbrdf_texture_own_decoder(testing_path("spec.exr"), &info, err), err);
  CHECK(info.own && info.size > 0);
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, testing_path("spec.exr"), err), err);
  if (r) {
    CHECK(texture_latent_reader_info(r)->format_version == 2);
    CHECK(strstr(texture_latent_reader_info(r)->accuracy, "level=specialised;") != NULL);
    texture_latent_reader_close(r);
  }
}

static int cancel_in_fit(void *user, const char *stage, double done, double total) {
  int *seen = user;
  if (!strcmp(stage, "ground truth")) seen[0]++;
  if (strcmp(stage, "fit")) return 0;
  seen[1]++;
  return done >= 10;
}

static void test_cancel_in_fit(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = sharp_coat();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  int seen[2] = {0, 0};
  o.accuracy = NBRDF_BAKE_FITTED;
  o.budget = 8.0;
  o.progress = cancel_in_fit;
  o.user = seen;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, testing_path("cancel.exr"), NULL, err), NBRDF_ERR_CANCELLED, err,
              "cancelled during the fit");
  CHECK(seen[0] >= 1 && seen[1] >= 1);
  struct stat sb;
  CHECK(stat(testing_path("cancel.exr"), &sb) != 0);
}

static void test_bad_options(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = sharp_coat();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.accuracy = (nbrdf_bake_accuracy)7;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, testing_path("bad.exr"), NULL, err), NBRDF_ERR_ARGUMENT, err,
              "fast, fitted, specialised, compact or auto");
  o.accuracy = NBRDF_BAKE_FITTED;
  o.budget = NAN;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, testing_path("bad.exr"), NULL, err), NBRDF_ERR_ARGUMENT, err,
              "budget");
  o.budget = 0.3;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, testing_path("bad.exr"), NULL, err), NBRDF_ERR_ARGUMENT, err,
              "too small");
  struct stat sb;
  CHECK(stat(testing_path("bad.exr"), &sb) != 0);
  CHECK(nbrdf_bake_accuracy_parse("fitted") == NBRDF_BAKE_FITTED);
  CHECK(nbrdf_bake_accuracy_parse("Fitted") == -1);
}

int main(int argc, char **argv) {
  testing_one_blas_thread(argc, argv);
  nbrdf_error e, *err = &e;
  char bundle[1024];
  snprintf(bundle, sizeof bundle, "%s/models/default", testing_source_dir());
  CHECK_OK(nbrdf_model_load(bundle, &model, err), err);
  if (!model) return testing_finish();
  RUN(test_plan);
  RUN(test_select);
  RUN(test_correction);
  RUN(test_truth_threads);
  RUN(test_bad_options);
  RUN(test_cancel_in_fit);
  RUN(test_fitted_constant);
  RUN(test_specialised_constant);
  nbrdf_model_destroy(model);
  return testing_finish();
}
