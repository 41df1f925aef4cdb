/* Decoder training end to end on a tiny data set: the loss falls, a run
 * interrupted and resumed from its checkpoint ends with the same weights as
 * an uninterrupted one, a checkpoint of other data is refused, per-BRDF loss
 * weights take effect, and the base tables fitted with the trained decoder
 * (warped axes) load and reproduce their nodes; a fine-tune (--init-bundle)
 * starts from the bundle's weights and the latents it gives each BRDF. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/bundle.h"
#include "nn/safetensors.h"
#include "testing.h"
#include "train/checkpoint.h"
#include "train/dataset.h"
#include "train/params_latent.h"
#include "train/samples.h"
#include "train/table_fit.h"
#include "train/train_decoder.h"

static char *path_of(const char *name) {
  static char buf[8][512];
  static int next;
  char *p = buf[next++ % 8];
  snprintf(p, 512, "%s/%s", testing_tmpdir(), name);
  return p;
}

static void make_data(const char *path, uint64_t seed) {
  train_dataset_settings s = TRAIN_DATASET_SETTINGS_DEFAULT;
  s.kind = TRAIN_CONDUCTOR;
  s.count = 12;
  s.seed = seed;
  s.incident = 4;
  s.outgoing = 32;
  s.sampled = 16;
  s.threads = 1;
  nbrdf_error err;
  CHECK_OK(train_dataset_write(path, &s, NULL, &err), &err);
}

static train_decoder_settings tiny(const char *const *data, const char *run, int64_t steps) {
  train_decoder_settings s;
  train_decoder_settings_default(&s);
  nbrdf_error err;
  CHECK_OK(model_decoder_preset("small", 32, &s.arch, &err), &err);
  s.data = data, s.n_data = 1, s.run_dir = run;
  s.steps = steps;
  s.rows_per_brdf = 32;
  s.lr_weights = 3e-3f;
  s.log_every = 10;
  s.validation_brdfs = 0; /* a held-out layered BRDF costs seconds; not needed here */
  return s;
}

static double first_logged_loss(const char *log) {
  FILE *f = fopen(log, "r");
  double loss = NAN;
  char line[256];
  if (f && fgets(line, sizeof line, f) && fgets(line, sizeof line, f)) {
    long long step;
    double sec;
    if (sscanf(line, "%lld,%lf,%lf", &step, &sec, &loss) != 3) loss = NAN;
  }
  if (f) fclose(f);
  return loss;
}

static float *load_params(const char *path, size_t *n) {
  model_decoder *dec = NULL;
  nbrdf_error err;
  CHECK_OK(model_decoder_load(path, &dec, &err), &err);
  if (!dec) return NULL;
  *n = nn_param_count(dec->nn);
  float *p = malloc(*n * sizeof *p);
  memcpy(p, nn_params(dec->nn), *n * sizeof *p);
  model_decoder_destroy(dec);
  return p;
}

static void test_loss_falls_and_resume_is_exact(void) {
  const char *data[1] = {path_of("c.nbds")};
  make_data(data[0], 3);
  nbrdf_error err;
  train_decoder_result r;
  train_decoder_settings s = tiny(data, path_of("run_a"), 120);
  CHECK_OK(train_decoder_run(&s, &r, &err), &err);
  CHECK(r.finished && r.steps_done == 120 && r.resumed_from == 0);
  double first = first_logged_loss(path_of("run_a/log.csv"));
  CHECK_MSG(r.train_loss < 0.5 * first, "loss %g -> %g: did not halve", first, r.train_loss);

  /* The same run, stopped at step 40 (the trainer's stop limit), then resumed. */
  s = tiny(data, path_of("run_b"), 120);
  s.stop_at_step = 40;
  CHECK_FAILS(train_decoder_run(&s, &r, &err), NBRDF_ERR_CANCELLED, &err, "resume");
  CHECK(r.steps_done == 40);
  s.stop_at_step = 0;
  CHECK_OK(train_decoder_run(&s, &r, &err), &err);
  CHECK(r.resumed_from == 40 && r.steps_done == 120 && !r.legacy_resume);
  size_t na = 0, nb = 0;
  float *a = load_params(path_of("run_a/decoder.safetensors"), &na);
  float *b = load_params(path_of("run_b/decoder.safetensors"), &nb);
  CHECK(a && b && na == nb && na > 0);
  if (a && b && na == nb) CHECK_MSG(!memcmp(a, b, na * sizeof *a), "resumed weights differ");
  free(a), free(b);

  /* Another setting is refused, naming it and both values. */
  s = tiny(data, path_of("run_b"), 130);
  s.lr_latent *= 2;
  CHECK_FAILS(train_decoder_run(&s, &r, &err), NBRDF_ERR_MISMATCH, &err, "lr-latent = 0.02");
  /* A checkpoint made from other data is refused, naming the data. */
  const char *other[1] = {path_of("d.nbds")};
  make_data(other[0], 4);
  s = tiny(other, path_of("run_b"), 130);
  CHECK_FAILS(train_decoder_run(&s, &r, &err), NBRDF_ERR_MISMATCH, &err, "data = ");
}

/* --brdf-weight: the weighted run still learns, ends elsewhere than the
 * unweighted one (the weights reach the gradient), and a bad power is refused. */
/* Rewrites a checkpoint the way runs wrote them before nbrdf.options existed
 * (nbrdf.spec and nbrdf.data metadata, the same tensors). */
static void make_legacy(const char *path, const char *const *data,
                        const model_decoder_config *arch) {
  nbrdf_error err;
  nn_st_reader *r = NULL;
  nn_st_writer *w = NULL;
  train_samples d;
  char key[1024], *spec = NULL;
  CHECK_OK(train_samples_load(1, data, &d, &err), &err);
  train_checkpoint_data_key(&d, key, sizeof key);
  train_samples_free(&d);
  CHECK_OK(nn_spec_to_json(&arch->spec, &spec, &err), &err);
  CHECK_OK(nn_st_open(path, &r, &err), &err);
  CHECK_OK(nn_st_writer_create(&w, &err), &err);
  if (!r || !w || !spec) return;
  static const char *const names[] = {"decoder.params", "latents",        "adam.latents.m",
                                      "adam.latents.v", "adam.weights.m", "adam.weights.v"};
  for (size_t k = 0; k < 6; k++) {
    const nn_st_tensor *t = nn_st_find(r, names[k]);
    CHECK(t != NULL);
    if (t) CHECK_OK(nn_st_writer_add(w, names[k], 1, t->shape, t->data, &err), &err);
  }
  nn_st_writer_set_metadata(w, "nbrdf.format", TRAIN_DECODER_CHECKPOINT_FORMAT, &err);
  nn_st_writer_set_metadata(w, "nbrdf.step", nn_st_metadata_get(r, "nbrdf.step"), &err);
  nn_st_writer_set_metadata(w, "nbrdf.spec", spec, &err);
  nn_st_writer_set_metadata(w, "nbrdf.data", key, &err);
  CHECK(nn_st_metadata_get(r, "nbrdf.options") != NULL);
  nn_st_close(r);
  CHECK_OK(nn_st_writer_save(w, path, NULL, &err), &err);
  nn_st_writer_destroy(w);
  free(spec);
}

/* A checkpoint written before nbrdf.options resumes (checked the old way, and
 * said so) to the bytes of a run that never stopped; one of another
 * architecture is still refused. */
static void test_legacy_checkpoint(void) {
  const char *data[1] = {path_of("c.nbds")};
  nbrdf_error err;
  train_decoder_result r;
  train_decoder_settings s = tiny(data, path_of("run_legacy"), 120);
  s.stop_at_step = 40;
  CHECK_FAILS(train_decoder_run(&s, &r, &err), NBRDF_ERR_CANCELLED, &err, "step 40");
  make_legacy(path_of("run_legacy/checkpoint.safetensors"), data, &s.arch);
  train_decoder_settings other = tiny(data, path_of("run_legacy"), 120);
  CHECK_OK(model_decoder_preset("medium", 32, &other.arch, &err), &err);
  CHECK_FAILS(train_decoder_run(&other, &r, &err), NBRDF_ERR_MISMATCH, &err,
              "decoder architecture");
  s.stop_at_step = 0;
  CHECK_OK(train_decoder_run(&s, &r, &err), &err);
  CHECK(r.legacy_resume && r.resumed_from == 40 && r.steps_done == 120);
  size_t na = 0, nb = 0;
  float *a = load_params(path_of("run_a/decoder.safetensors"), &na);
  float *b = load_params(path_of("run_legacy/decoder.safetensors"), &nb);
  if (a && b && na == nb)
    CHECK_MSG(!memcmp(a, b, na * sizeof *a), "a run resumed from a legacy checkpoint differs");
  free(a), free(b);
}

static void test_brdf_weight(void) {
  const char *data[1] = {path_of("c.nbds")};
  nbrdf_error err;
  train_decoder_result r;
  train_decoder_settings s = tiny(data, path_of("run_w0"), 60);
  CHECK_OK(train_decoder_run(&s, &r, &err), &err);
  s = tiny(data, path_of("run_w1"), 60);
  s.brdf_weight = 1.0;
  CHECK_OK(train_decoder_run(&s, &r, &err), &err);
  double first = first_logged_loss(path_of("run_w1/log.csv"));
  CHECK_MSG(r.train_loss < 0.7 * first, "weighted loss %g -> %g", first, r.train_loss);
  size_t na = 0, nb = 0;
  float *a = load_params(path_of("run_w0/decoder.safetensors"), &na);
  float *b = load_params(path_of("run_w1/decoder.safetensors"), &nb);
  CHECK(a && b && na == nb && na > 0);
  if (a && b && na == nb) CHECK_MSG(memcmp(a, b, na * sizeof *a), "BRDF weights had no effect");
  free(a), free(b);
  s = tiny(data, path_of("run_w2"), 10);
  s.brdf_weight = 3.0;
  CHECK_FAILS(train_decoder_run(&s, &r, &err), NBRDF_ERR_ARGUMENT, &err, "weight power");
}

/* --energy: the penalty reaches the weights (the run ends elsewhere than
 * without it) and a run stopped and resumed equals one that never stopped
 * (the penalised BRDFs and directions are functions of the step). */
static void test_energy_penalty(void) {
  const char *data[1] = {path_of("c.nbds")};
  nbrdf_error err;
  train_decoder_result r;
  train_decoder_settings s = tiny(data, path_of("run_e0"), 40);
  CHECK_OK(train_decoder_run(&s, &r, &err), &err);
  s = tiny(data, path_of("run_e1"), 40);
  /* A large λ: the conductors' albedo ceilings must bind on a young decoder. */
  s.energy.lambda = 50.0f, s.energy.samples = 32, s.energy_brdfs = 4;
  CHECK_OK(train_decoder_run(&s, &r, &err), &err);
  s = tiny(data, path_of("run_e2"), 40);
  s.energy.lambda = 50.0f, s.energy.samples = 32, s.energy_brdfs = 4;
  s.stop_at_step = 20;
  CHECK_FAILS(train_decoder_run(&s, &r, &err), NBRDF_ERR_CANCELLED, &err, "resume");
  s.stop_at_step = 0;
  CHECK_OK(train_decoder_run(&s, &r, &err), &err);
  CHECK(r.resumed_from == 20 && r.steps_done == 40);
  size_t n0 = 0, n1 = 0, n2 = 0;
  float *a = load_params(path_of("run_e0/decoder.safetensors"), &n0);
  float *b = load_params(path_of("run_e1/decoder.safetensors"), &n1);
  float *c = load_params(path_of("run_e2/decoder.safetensors"), &n2);
  CHECK(a && b && c && n0 == n1 && n1 == n2 && n0 > 0);
  if (a && b && c && n0 == n1 && n1 == n2) {
    CHECK_MSG(memcmp(a, b, n0 * sizeof *a), "the energy penalty had no effect");
    CHECK_MSG(!memcmp(b, c, n0 * sizeof *b), "resumed weights differ with the energy penalty");
  }
  free(a), free(b), free(c);
}

static void test_tables_from_trained_decoder(void) {
  model_decoder *dec = NULL;
  nbrdf_error err;
  CHECK_OK(model_decoder_load(path_of("run_a/decoder.safetensors"), &dec, &err), &err);
  if (!dec) return;
  train_table_settings ts = TRAIN_TABLE_SETTINGS_DEFAULT;
  ts.alpha_nodes = 3, ts.eta_nodes = 3, ts.r0_nodes = 3, ts.steps = 30;
  ts.eta_warp = 2.0, ts.r0_warp = 2.0;
  model_base_table t[2];
  CHECK_OK(train_tables_fit(dec, &ts, t, &err), &err);
  const model_base_table *const parts[2] = {&t[0], &t[1]};
  CHECK_OK(model_tables_save(parts, path_of("tables.safetensors"), &err), &err);
  /* At a node, the look-up returns the projected latent itself. */
  double a = t[1].axis[0][1], r0 = t[1].axis[1][1];
  float got[32];
  CHECK_OK(model_base_table_lookup(&t[1], 1, &a, &r0, 1, got, NULL, &err), &err);
  const float *want = t[1].latents + ((size_t)1 * t[1].n[1] + 1) * 32;
  for (int j = 0; j < 32; j++)
    CHECK_NEAR(got[j], want[j], 1e-6);
  /* Warped axes: the middle node sits at u = 1/2, squared. */
  CHECK_NEAR(t[0].axis[1][1], 1.05 + 0.95 * 0.25, 1e-6);
  CHECK_NEAR(t[1].axis[1][1], 0.25, 1e-7);
  CHECK(t[1].axis[1][0] == 0.0f && t[1].axis[1][2] == 1.0f);
  /* Projection moved the latents away from their zero start. */
  double norm = 0;
  for (size_t k = 0; k < (size_t)t[0].n[0] * t[0].n[1] * 32; k++)
    norm += fabs(t[0].latents[k]);
  CHECK(norm > 0 && isfinite(norm));
  model_base_table_free(&t[0]);
  model_base_table_free(&t[1]);
  /* --eta-min 1: the dielectric grid starts at η = 1 (no coat), so a look-up
   * there is not clamped; without it, η = 1 is clamped to 1.05 and flagged. */
  ts.eta_min = 1.0, ts.steps = 5;
  CHECK_OK(train_tables_fit(dec, &ts, t, &err), &err);
  CHECK(t[0].axis[1][0] == 1.0f && t[0].axis[1][2] == 2.0f);
  double a1 = 0.1, eta1 = 1.0;
  unsigned char clamped = 9;
  CHECK_OK(model_base_table_lookup(&t[0], 1, &a1, &eta1, 0, got, &clamped, &err), &err);
  CHECK(clamped == 0);
  model_base_table_free(&t[0]);
  model_base_table_free(&t[1]);
  ts.eta_min = 1.05;
  CHECK_OK(train_tables_fit(dec, &ts, t, &err), &err);
  CHECK_OK(model_base_table_lookup(&t[0], 1, &a1, &eta1, 0, got, &clamped, &err), &err);
  CHECK(clamped == 2);
  model_base_table_free(&t[0]);
  model_base_table_free(&t[1]);
  ts.eta_min = 0.9;
  CHECK_FAILS(train_tables_fit(dec, &ts, t, &err), NBRDF_ERR_ARGUMENT, &err, "first eta node");
  model_decoder_destroy(dec);
}

static void test_init_from_bundle(void) {
  const char *data[1] = {path_of("c.nbds")}; /* test_loss_falls_and_resume_is_exact's */
  char dir[512];
  snprintf(dir, sizeof dir, "%s/init-bundle", testing_tmpdir());
  nbrdf_model *m = NULL;
  nbrdf_error err;
  CHECK_OK(model_bundle_init_random(dir, "init-test", 5, "small", &err), &err);
  CHECK_OK(nbrdf_model_load(dir, &m, &err), &err);
  if (!m) return;
  /* One step at zero learning rates: what the run starts from is what it saves. */
  train_decoder_settings s = tiny(data, path_of("run_init"), 1);
  s.init = m, s.lr_weights = 0, s.lr_latent = 0, s.latent_l2 = 0;
  s.arch.spec.n_layers = 0; /* ignored: the bundle's architecture is the run's */
  train_decoder_result r;
  CHECK_OK(train_decoder_run(&s, &r, &err), &err);
  size_t n = 0;
  float *w = load_params(path_of("run_init/decoder.safetensors"), &n);
  CHECK(w && n == nn_param_count(m->decoder->nn));
  if (w && n == nn_param_count(m->decoder->nn))
    CHECK_MSG(!memcmp(w, nn_params(m->decoder->nn), n * sizeof *w), "weights not the bundle's");
  free(w);
  train_samples d;
  CHECK_OK(train_samples_load(1, data, &d, &err), &err);
  nn_st_reader *ck = NULL;
  CHECK_OK(nn_st_open(path_of("run_init/checkpoint.safetensors"), &ck, &err), &err);
  int64_t shape[1] = {(int64_t)d.n_brdfs * 32};
  const float *lat = NULL;
  if (ck) CHECK_OK(nn_st_expect(ck, "latents", 1, shape, &lat, NULL), &err);
  for (size_t b = 0; lat && b < d.n_brdfs; b++) {
    float want[32];
    CHECK_OK(train_params_bundle_latent(m, &d.params[b], want, &err), &err);
    CHECK_MSG(!memcmp(want, lat + b * 32, sizeof want), "BRDF %zu: latent not the bundle's", b);
  }
  nn_st_close(ck);
  train_samples_free(&d);
  /* A resume from another start is refused, naming it. */
  s.init = NULL, s.steps = 2;
  CHECK_OK(model_decoder_preset("small", 32, &s.arch, &err), &err);
  CHECK_FAILS(train_decoder_run(&s, &r, &err), NBRDF_ERR_MISMATCH, &err, "init-bundle");
  nbrdf_model_destroy(m);
}

int main(void) {
  RUN(test_loss_falls_and_resume_is_exact);
  RUN(test_legacy_checkpoint);
  RUN(test_brdf_weight);
  RUN(test_energy_penalty);
  RUN(test_tables_from_trained_decoder);
  RUN(test_init_from_bundle);
  return testing_finish();
}
