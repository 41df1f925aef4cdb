/* --accuracy auto (issue 35, src/bake/bake_auto.c) on a sharp low-IOR coat, where the
 * universal networks are poor: a target fast meets stops at fast (one level tried, the texture
 * fast's bytes); a target nothing meets climbs, bakes the best level reached (never one worse
 * than fast) and says what budget would help, or with `require` fails leaving no file; the
 * header records the request and the outcome; a fit worse than fast beyond the margin falls
 * back. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "bake/bake_accuracy.h"
#include "bake/bake_auto.h"
#include "nbrdf/bake.h"
#include "testing.h"
#include "texture/latent_exr.h"

static nbrdf_model *model;

static nbrdf_bake_inputs sharp_coat(void) {
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  const float v[NBRDF_BAKE_PARAM_COUNT] = {0.01f, 1.05f, 0.5f, 0.95f, 1.0f, 0.0f};
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    nbrdf_bake_param_constant(&in.param[id], v[id]);
  return in;
}

static char warned[1024];
static void on_warning(void *user, const char *message) {
  (void)user;
  if (!strncmp(message, "auto:", 5)) snprintf(warned, sizeof warned, "%s", message);
}

static void accuracy_attr(const char *path, char *buf, size_t cap) {
  nbrdf_error e;
  texture_latent_reader *r = NULL;
  buf[0] = '\0';
  if (texture_latent_reader_open(&r, testing_path(path), &e) != NBRDF_OK) return;
  snprintf(buf, cap, "%s", texture_latent_reader_info(r)->accuracy);
  texture_latent_reader_close(r);
}

static void test_fast_meets(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = sharp_coat();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.accuracy = NBRDF_BAKE_AUTO;
  o.max_error = 900.0;
  o.budget = 4.0;
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(model, &in, &o, testing_path("auto_fast.exr"), &rep, err), err);
  CHECK(rep.requested == NBRDF_BAKE_AUTO && rep.accuracy == NBRDF_BAKE_FAST);
  CHECK(rep.met && rep.tried == 1 && rep.tried_level[0] == NBRDF_BAKE_FAST);
  CHECK_MSG(rep.tried_error[0] > 0.0 && rep.tried_error[0] == rep.heldout_error_fast,
            "fast error %g, report %g", rep.tried_error[0], rep.heldout_error_fast);
  char acc[1024];
  accuracy_attr("auto_fast.exr", acc, sizeof acc);
  CHECK_MSG(!strncmp(acc, "level=fast; requested=auto; chosen=fast; maxError=900; met=1", 60),
            "accuracy attribute '%s'", acc);
  /* The texels are fast's: the same file as a fast bake but for the header. */
  o = (nbrdf_bake_options)NBRDF_BAKE_OPTIONS_DEFAULT;
  CHECK_OK(nbrdf_bake(model, &in, &o, testing_path("fast.exr"), &rep, err), err);
  nbrdf_decoder_info info;
  CHECK_OK(nbrdf_texture_own_decoder(testing_path("auto_fast.exr"), &info, err), err);
  CHECK(!info.own);
}

static void test_nothing_meets(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = sharp_coat();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.accuracy = NBRDF_BAKE_AUTO;
  o.max_error = 0.01;
  o.budget = 4.0;
  o.warning = on_warning;
  warned[0] = '\0';
  nbrdf_bake_report rep;
  CHECK_OK(nbrdf_bake(model, &in, &o, testing_path("auto_best.exr"), &rep, err), err);
  CHECK(!rep.met && rep.tried == 3 && rep.tried_level[1] == NBRDF_BAKE_FITTED &&
        rep.tried_level[2] == NBRDF_BAKE_SPECIALISED);
  /* The best level not worse than fast is baked. */
  double best = rep.tried_error[0];
  nbrdf_bake_accuracy best_level = NBRDF_BAKE_FAST;
  for (int i = 1; i < rep.tried; i++)
    if (rep.tried_error[i] < best &&
        rep.tried_error[i] <= rep.tried_error[0] + BAKE_FALLBACK_MARGIN)
      best = rep.tried_error[i], best_level = rep.tried_level[i];
  CHECK_MSG(rep.accuracy == best_level, "baked %s, best %s", nbrdf_bake_accuracy_name(rep.accuracy),
            nbrdf_bake_accuracy_name(best_level));
  printf("  sharp low-IOR coat at budget 4: fast %.2f %%, fitted %.2f %%, specialised %.2f %%; "
         "suggested budget %g\n",
         100 * rep.tried_error[0], 100 * rep.tried_error[1], 100 * rep.tried_error[2],
         rep.suggested_budget);
  CHECK(rep.suggested_budget == 0.0 || rep.suggested_budget > 4.0);
  CHECK_MSG(strstr(warned, "no level within the budget meets 0.01 %") != NULL, "warning '%s'",
            warned);
  char acc[1024];
  accuracy_attr("auto_best.exr", acc, sizeof acc);
  CHECK_MSG(strstr(acc, "requested=auto;") && strstr(acc, "met=0;") && strstr(acc, "tried=fast:") &&
                strstr(acc, "suggestedBudget="),
            "accuracy attribute '%s'", acc);
  /* require: the same outcome is a failure, and no file. */
  o.require = 1;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, testing_path("auto_req.exr"), NULL, err),
              NBRDF_ERR_UNSUPPORTED, err, "no level within the budget meets 0.01 %");
  struct stat sb;
  CHECK(stat(testing_path("auto_req.exr"), &sb) != 0);
}

static void test_options(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = sharp_coat();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.accuracy = NBRDF_BAKE_AUTO;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, testing_path("bad.exr"), NULL, err), NBRDF_ERR_ARGUMENT,
              err, "auto needs max_error");
  o.max_error = 5.0;
  o.budget = 0.3;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, testing_path("bad.exr"), NULL, err), NBRDF_ERR_ARGUMENT,
              err, "too small for 'fitted'");
  CHECK(nbrdf_bake_accuracy_parse("auto") == NBRDF_BAKE_AUTO);
  CHECK(!strcmp(nbrdf_bake_accuracy_name(NBRDF_BAKE_AUTO), "auto"));
}

static void test_worse_than_fast(void) {
  bake_fit_result r;
  memset(&r, 0, sizeof r);
  r.heldout = 4, r.heldout_error_fast = 0.05;
  r.heldout_error = 0.05 + 0.5 * BAKE_FALLBACK_MARGIN;
  CHECK(!bake_fit_worse_than_fast(&r)); /* within the margin */
  r.heldout_error = 0.05 + 2.0 * BAKE_FALLBACK_MARGIN;
  CHECK(bake_fit_worse_than_fast(&r));
  r.heldout = 0; /* nothing measured: nothing to fall back from */
  CHECK(!bake_fit_worse_than_fast(&r));
}

int main(int argc, char **argv) {
  testing_one_blas_thread(argc, argv);
  nbrdf_error e, *err = &e;
  char bundle[1024];
  snprintf(bundle, sizeof bundle, "%s/models/default", testing_source_dir());
  CHECK_OK(nbrdf_model_load(bundle, &model, err), err);
  if (!model) return testing_finish();
  RUN(test_worse_than_fast);
  RUN(test_options);
  RUN(test_fast_meets);
  RUN(test_nothing_meets);
  nbrdf_model_destroy(model);
  return testing_finish();
}
