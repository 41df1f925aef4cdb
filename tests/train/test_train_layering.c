/* The training chain after the decoder on a tiny data set: layering pairs
 * from a decoder run's two-layer BRDFs, a layering fit whose loss falls, and
 * a bundle assembled from the trained parts that loads and layers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "model/bundle.h"
#include "testing.h"
#include "train/dataset.h"
#include "train/samples.h"
#include "train/table_fit.h"
#include "train/train_decoder.h"
#include "train/train_layering.h"
#include "train/train_sampler.h"

static char *path_of(const char *name) {
  static char buf[8][512];
  static int next;
  char *p = buf[next++ % 8];
  snprintf(p, 512, "%s/%s", testing_tmpdir(), name);
  return p;
}

/* Cancels at the first report inside epoch 8; after epoch 7's report it waits
 * out the progress throttle so that the next batch's report reaches it. */
static int cancel_inside_epoch_8(void *user, const char *stage, double done, double total) {
  (void)user, (void)stage, (void)total;
  if (done > 7.0 && done < 8.0) return 1;
  if (done == 7.0) nanosleep(&(struct timespec){0, 150000000L}, NULL);
  return 0;
}

/* The decoded loss: it falls from the latent-trained network it starts from,
 * a run resumed from its checkpoint ends with the same weights as one that
 * never stopped, and a checkpoint of other settings is refused. */
static void test_decoded(const train_samples *d, model_decoder *dec, const model_base_table t[2],
                         const model_layering *init) {
  nbrdf_error err;
  train_layering_settings s = TRAIN_LAYERING_SETTINGS_DEFAULT;
  s.epochs = 40, s.batch = 8, s.validation_every = 6, s.rows_per_pair = 16;
  model_layering *a = NULL, *b = NULL, *c = NULL, *fresh = NULL;
  train_layering_result r;
  /* The objective on all samples of the training pairs, before and after. */
  train_layering_pairs tp, vp;
  double before = NAN, after = NAN, from_latent = NAN;
  CHECK_OK(train_layering_pairs_make(d, NULL, t, 2, s.validation_every, &tp, &vp, &err), &err);
  CHECK_OK(model_layering_create(s.preset, 32, s.seed, &fresh, &err), &err);
  CHECK_OK(train_layering_decoded_loss(fresh, dec, s.loss, d, &tp, &before, &err), &err);
  CHECK_OK(train_layering_fit_decoded(d, dec, t, &s, &a, &r, &err), &err);
  CHECK(r.pairs == 20 && r.validation_pairs == 4 && r.epochs_done == 40 && r.resumed_from == 0);
  if (a) CHECK_OK(train_layering_decoded_loss(a, dec, s.loss, d, &tp, &after, &err), &err);
  /* The 40-step decoder bounds what any latent reaches (0.164 after 100 epochs). */
  CHECK_MSG(after < 0.85 * before, "decoded loss %g -> %g", before, after);
  CHECK(isfinite(r.val_decoded) && r.val_decoded > 0);
  /* Started from the latent-trained network, it ends no worse than that start. */
  model_layering_destroy(a);
  s.init = init, a = NULL;
  CHECK_OK(train_layering_decoded_loss(init, dec, s.loss, d, &tp, &from_latent, &err), &err);
  CHECK_OK(train_layering_fit_decoded(d, dec, t, &s, &a, &r, &err), &err);
  if (a) CHECK_OK(train_layering_decoded_loss(a, dec, s.loss, d, &tp, &after, &err), &err);
  CHECK_MSG(after < from_latent, "decoded loss from the latent-trained net %g -> %g", from_latent,
            after);
  train_layering_pairs_free(&tp), train_layering_pairs_free(&vp);
  model_layering_destroy(fresh);

  s.log_path = NULL, s.epochs = 12, s.init = NULL;
  CHECK_OK(train_layering_fit_decoded(d, dec, t, &s, &b, &r, &err), &err);
  s.checkpoint = path_of("dec.ckpt"), s.epochs = 5;
  model_layering *half = NULL;
  CHECK_OK(train_layering_fit_decoded(d, dec, t, &s, &half, &r, &err), &err);
  s.epochs = 12;
  CHECK_OK(train_layering_fit_decoded(d, dec, t, &s, &c, &r, &err), &err);
  CHECK(r.resumed_from == 5 && r.epochs_done == 12);
  if (b && c) {
    size_t n = nn_param_count(b->nn);
    CHECK(n == nn_param_count(c->nn) &&
          !memcmp(nn_params(b->nn), nn_params(c->nn), n * sizeof(float)));
  }
  /* Cancelled inside an epoch (the callback is asked after every batch), the
   * run saves the batch it reached and resumes there exactly. */
  model_layering *cut = NULL, *d2 = NULL;
  s.checkpoint = path_of("dec_cut.ckpt"), s.progress = cancel_inside_epoch_8;
  CHECK(train_layering_fit_decoded(d, dec, t, &s, &cut, &r, &err) == NBRDF_ERR_CANCELLED);
  CHECK_MSG(cut == NULL && strstr(err.message, "in epoch 8 after batch 1 of"), "%s",
            err.message);
  s.progress = NULL;
  CHECK_OK(train_layering_fit_decoded(d, dec, t, &s, &d2, &r, &err), &err);
  CHECK(r.resumed_from == 7 && r.epochs_done == 12);
  if (b && d2) {
    size_t n = nn_param_count(b->nn);
    CHECK_MSG(!memcmp(nn_params(b->nn), nn_params(d2->nn), n * sizeof(float)),
              "a run resumed inside an epoch differs from one that never stopped");
  }
  model_layering_destroy(d2);
  s.checkpoint = path_of("dec.ckpt");
  s.rows_per_pair = 8;
  model_layering *x = NULL;
  CHECK(train_layering_fit_decoded(d, dec, t, &s, &x, &r, &err) == NBRDF_ERR_MISMATCH);
  CHECK(x == NULL && strstr(err.message, "dec.ckpt"));
  model_layering_destroy(a), model_layering_destroy(b), model_layering_destroy(c);
  model_layering_destroy(half);
}

static void test_layering_chain(void) {
  nbrdf_error err;
  train_dataset_settings ds = TRAIN_DATASET_SETTINGS_DEFAULT;
  ds.kind = TRAIN_LAYERED2, ds.count = 24, ds.seed = 5, ds.incident = 2, ds.outgoing = 16;
  ds.sampled = 8, ds.spp = 32, ds.threads = 1;
  const char *data[1] = {path_of("l2.nbds")};
  CHECK_OK(train_dataset_write(data[0], &ds, NULL, &err), &err);

  train_decoder_settings s;
  train_decoder_settings_default(&s);
  CHECK_OK(model_decoder_preset("small", 32, &s.arch, &err), &err);
  s.data = data, s.n_data = 1, s.run_dir = path_of("run"), s.steps = 40, s.rows_per_brdf = 16;
  s.validation_brdfs = 0;
  train_decoder_result dr;
  CHECK_OK(train_decoder_run(&s, &dr, &err), &err);

  model_decoder *dec = NULL;
  CHECK_OK(model_decoder_load(path_of("run/decoder.safetensors"), &dec, &err), &err);
  if (!dec) return;
  train_table_settings ts = TRAIN_TABLE_SETTINGS_DEFAULT;
  ts.alpha_nodes = 3, ts.eta_nodes = 2, ts.r0_nodes = 2, ts.steps = 20;
  model_base_table t[2];
  CHECK_OK(train_tables_fit(dec, &ts, t, &err), &err);
  /* The tables stopped after 7 of their 20 steps and resumed: the same bytes. */
  model_base_table t2[2];
  ts.checkpoint = path_of("tables.ckpt"), ts.stop_at_step = 7;
  CHECK(train_tables_fit(dec, &ts, t2, &err) == NBRDF_ERR_CANCELLED);
  ts.stop_at_step = 0;
  CHECK_OK(train_tables_fit(dec, &ts, t2, &err), &err);
  for (int k = 0; k < 2; k++) {
    size_t n = (size_t)t[k].n[0] * (size_t)t[k].n[1] * (size_t)t[k].dim;
    CHECK_MSG(!memcmp(t[k].latents, t2[k].latents, n * sizeof(float)),
              "resumed table %d differs from the uninterrupted one", k);
    model_base_table_free(&t2[k]);
  }

  train_samples d;
  CHECK_OK(train_samples_load(1, data, &d, &err), &err);
  float *lat = malloc(d.n_brdfs * 32 * sizeof *lat);
  CHECK_OK(
      train_checkpoint_latents(path_of("run/checkpoint.safetensors"), d.n_brdfs, 32, lat, &err),
      &err);
  train_layering_settings ls = TRAIN_LAYERING_SETTINGS_DEFAULT;
  ls.epochs = 60, ls.batch = 8, ls.validation_every = 6, ls.log_path = path_of("lay.csv");
  model_layering *net = NULL;
  train_layering_result lr;
  CHECK_OK(train_layering_fit(&d, lat, dec, t, &ls, &net, &lr, &err), &err);
  CHECK(lr.pairs == 20 && lr.validation_pairs == 4);
  CHECK(isfinite(lr.val_decoded) && isfinite(lr.val_decoded_oracle));
  /* The first logged epoch (10) against the last: the training loss fell. */
  FILE *f = fopen(path_of("lay.csv"), "r");
  char line[256];
  double first = NAN;
  int e;
  double tl;
  if (f && fgets(line, sizeof line, f) && fgets(line, sizeof line, f) &&
      sscanf(line, "%d,%lf", &e, &tl) == 2)
    first = tl;
  if (f) fclose(f);
  CHECK_MSG(lr.train_loss < 0.5 * first, "layering loss %g -> %g", first, lr.train_loss);
  /* Stopped inside epoch 26 and resumed from its checkpoint, the run ends with
   * the bytes of the one that never stopped (its shuffles come from one
   * generator across epochs: the checkpoint carries it); another seed is
   * refused, naming the option. */
  ls.log_path = NULL, ls.checkpoint = path_of("lat.ckpt"), ls.stop_at_step = 76;
  model_layering *cut = NULL, *resumed = NULL;
  CHECK(train_layering_fit(&d, lat, dec, t, &ls, &cut, &lr, &err) == NBRDF_ERR_CANCELLED);
  CHECK(cut == NULL);
  ls.stop_at_step = 0;
  CHECK_OK(train_layering_fit(&d, lat, dec, t, &ls, &resumed, &lr, &err), &err);
  CHECK(lr.resumed_from == 25 && lr.epochs_done == 60);
  if (net && resumed)
    CHECK_MSG(!memcmp(nn_params(net->nn), nn_params(resumed->nn),
                      nn_param_count(net->nn) * sizeof(float)),
              "a resumed latent-loss run differs from one that never stopped");
  model_layering_destroy(resumed);
  ls.seed = 2;
  CHECK(train_layering_fit(&d, lat, dec, t, &ls, &cut, &lr, &err) == NBRDF_ERR_MISMATCH);
  CHECK_MSG(strstr(err.message, "seed = 1") && strstr(err.message, "seed = 2"), "%s", err.message);
  ls.seed = 1, ls.checkpoint = NULL;
  test_decoded(&d, dec, t, net);

  /* The sampler: the fitted proxy is at least as close to the decoded BRDFs as
   * the cosine lobe it contains (w = 1), and the network's regression error
   * falls with training. */
  train_sampler_settings ss = TRAIN_SAMPLER_SETTINGS_DEFAULT;
  ss.incident = 2, ss.outgoing = 64, ss.epochs = 1, ss.batch = 8;
  model_sampler *smp = NULL, *smp1 = NULL;
  train_sampler_result sr1, sr;
  CHECK_OK(train_sampler_fit(dec, d.n_brdfs, lat, &ss, &smp1, &sr1, &err), &err);
  ss.epochs = 200;
  CHECK_OK(train_sampler_fit(dec, d.n_brdfs, lat, &ss, &smp, &sr, &err), &err);
  CHECK_MSG(sr.mean_ce_fit <= sr.mean_ce_cosine + 1e-9, "fit %g vs cosine %g", sr.mean_ce_fit,
            sr.mean_ce_cosine);
  CHECK_MSG(sr.rms_o < 0.5 * sr1.rms_o, "sampler rms %g -> %g", sr1.rms_o, sr.rms_o);
  model_sampler_destroy(smp1);
  /* Stopped inside epoch 101 and resumed: the bytes of the run that never stopped. */
  model_sampler *smp_resumed = NULL;
  ss.checkpoint = path_of("sampler.ckpt"), ss.stop_at_step = 301;
  CHECK(train_sampler_fit(dec, d.n_brdfs, lat, &ss, &smp1, &sr1, &err) == NBRDF_ERR_CANCELLED);
  ss.stop_at_step = 0;
  CHECK_OK(train_sampler_fit(dec, d.n_brdfs, lat, &ss, &smp_resumed, &sr1, &err), &err);
  CHECK(sr1.resumed_from == 301);
  if (smp && smp_resumed)
    CHECK_MSG(!memcmp(nn_params(smp->nn), nn_params(smp_resumed->nn),
                      nn_param_count(smp->nn) * sizeof(float)),
              "a resumed sampler run differs from one that never stopped");
  model_sampler_destroy(smp_resumed);
  ss.checkpoint = NULL;
  /* Ctrl-C reaches the network's training inside an epoch, not only at its end. */
  model_sampler *stopped = NULL;
  ss.progress = cancel_inside_epoch_8;
  CHECK(train_sampler_fit(dec, d.n_brdfs, lat, &ss, &stopped, &sr1, &err) == NBRDF_ERR_CANCELLED);
  CHECK(stopped == NULL);
  ss.progress = NULL;

  /* A bundle of the trained parts loads, and layering it gives finite latents. */
  model_bundle_parts parts = {.name = "tiny",
                              .trained = 1,
                              .seed = 1,
                              .decoder = dec,
                              .layering = net,
                              .sampler = smp,
                              .tables = {&t[0], &t[1]}};
  CHECK_OK(model_bundle_save(path_of("bundle"), &parts, NULL, &err), &err);
  nbrdf_model *m = NULL;
  CHECK_OK(nbrdf_model_load(path_of("bundle"), &m, &err), &err);
  if (m) {
    float top[32], bottom[32], out[32], a = 0.5f, sig = 2.0f;
    float a1 = 0.1f, eta = 1.5f, a2 = 0.3f, r0 = 0.9f;
    CHECK_OK(nbrdf_model_base_latents(m, NBRDF_BASE_DIELECTRIC, 1, &a1, &eta, NBRDF_RANGE_REFUSE,
                                      top, NULL, &err),
             &err);
    CHECK_OK(nbrdf_model_base_latents(m, NBRDF_BASE_CONDUCTOR, 1, &a2, &r0, NBRDF_RANGE_REFUSE,
                                      bottom, NULL, &err),
             &err);
    CHECK_OK(nbrdf_model_layer(m, 1, top, bottom, &a, &sig, out, &err), &err);
    for (int j = 0; j < 32; j++)
      CHECK(isfinite(out[j]));
    CHECK(nbrdf_model_is_trained(m));
  }
  nbrdf_model_destroy(m);
  model_sampler_destroy(smp);
  model_layering_destroy(net);
  free(lat);
  train_samples_free(&d);
  model_base_table_free(&t[0]);
  model_base_table_free(&t[1]);
  model_decoder_destroy(dec);
}

int main(void) {
  RUN(test_layering_chain);
  return testing_finish();
}
