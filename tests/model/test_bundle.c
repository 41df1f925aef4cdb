/* Networks and the model bundle on disk: save → load gives identical outputs,
 * damaged or mismatched bundles are refused with the file named, and the
 * public calls on a loaded model. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/rng.h"
#include "model/bundle.h"
#include "model/files.h"
#include "testing.h"

static char *path_in(const char *dir, const char *file) {
  static char buf[8][4096];
  static int next;
  char *p = buf[next++ % 8];
  snprintf(p, 4096, "%s/%s", dir, file);
  return p;
}

static void random_queries(core_rng *rng, size_t n, float *wi, float *wo) {
  for (size_t k = 0; k < 2 * n; k++) {
    double z = 0.05 + 0.95 * core_rng_uniform(rng), r = sqrt(1 - z * z);
    double phi = 2 * M_PI * core_rng_uniform(rng);
    float *w = k < n ? wi + 3 * k : wo + 3 * (k - n);
    w[0] = (float)(r * cos(phi)), w[1] = (float)(r * sin(phi)), w[2] = (float)z;
  }
}

static void copy_file(const char *from, const char *to) {
  char *bytes = NULL;
  size_t size = 0;
  if (model_read_file(from, UINT64_MAX, &bytes, &size, NULL) != NBRDF_OK) return;
  FILE *fp = fopen(to, "wb");
  if (fp) {
    fwrite(bytes, 1, size, fp);
    fclose(fp);
  }
  free(bytes);
}

/* Each network alone: save, load, same outputs bit for bit. */
static void test_network_round_trips(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  char dir[1024];
  snprintf(dir, sizeof dir, "%s", testing_tmpdir());
  core_rng rng;
  core_rng_init(&rng, 1, 0);
  enum { N = 37 };
  float lat[N * 32], lat2[N * 32], wi[N * 3], wo[N * 3], a[N], s[N];
  for (int i = 0; i < N * 32; i++)
    lat[i] = (float)core_rng_normal(&rng), lat2[i] = (float)core_rng_normal(&rng);
  for (int k = 0; k < N; k++)
    a[k] = (float)core_rng_uniform(&rng), s[k] = (float)(k % 6);
  random_queries(&rng, N, wi, wo);

  for (int p = 0; model_decoder_presets[p]; p++) {
    model_decoder_config cfg;
    model_decoder *dec = NULL, *back = NULL;
    CHECK_OK(model_decoder_preset(model_decoder_presets[p], 32, &cfg, err), err);
    CHECK_OK(model_decoder_create(&cfg, 11, &dec, err), err);
    CHECK_OK(model_decoder_save(dec, path_in(dir, "dec.safetensors"), NULL, err), err);
    CHECK_OK(model_decoder_load(path_in(dir, "dec.safetensors"), &back, err), err);
    if (!dec || !back) continue;
    CHECK(!strcmp(back->cfg.preset, model_decoder_presets[p]));
    CHECK(back->cfg.encoding.kind == cfg.encoding.kind && back->cfg.output == cfg.output);
    model_runner r1, r2;
    float f1[N], f2[N];
    CHECK_OK(model_runner_create(dec->nn, 16, NBRDF_NN_INFER, &r1, err), err);
    CHECK_OK(model_runner_create(back->nn, 16, NBRDF_NN_INFER, &r2, err), err);
    CHECK_OK(model_decoder_eval(dec, &r1, N, 1, lat, wi, wo, f1, err), err);
    CHECK_OK(model_decoder_eval(back, &r2, N, 1, lat, wi, wo, f2, err), err);
    CHECK(!memcmp(f1, f2, sizeof f1));
    /* Per-channel rows share the directions: channel c of query k = a 1-channel query. */
    float f3[N];
    CHECK_OK(model_decoder_eval(dec, &r1, N / 2, 2, lat, wi, wo, f3, err), err);
    float one[2];
    CHECK_OK(model_decoder_eval(dec, &r1, 1, 1, lat + 32 * 7, wi + 3 * 3, wo + 3 * 3, one, err),
             err);
    CHECK(fabsf(one[0] - f3[7]) <= 1e-5f * fmaxf(1.0f, fabsf(one[0])));
    if (p == 0) CHECK(model_decoder_macs(dec) == 1058560);
    model_runner_destroy(&r1);
    model_runner_destroy(&r2);
    model_decoder_destroy(dec);
    model_decoder_destroy(back);
  }

  model_layering *lay = NULL, *lay2 = NULL;
  CHECK_OK(model_layering_create("small", 32, 12, &lay, err), err);
  CHECK_OK(model_layering_save(lay, path_in(dir, "lay.safetensors"), NULL, err), err);
  nn_st_reader *r = NULL;
  CHECK_OK(nn_st_open(path_in(dir, "lay.safetensors"), &r, err), err);
  if (r) CHECK_OK(model_layering_read(r, &lay2, err), err);
  nn_st_close(r);
  if (lay && lay2) {
    model_runner r1, r2;
    static float o1[N * 32], o2[N * 32];
    CHECK_OK(model_runner_create(lay->nn, 8, NBRDF_NN_INFER, &r1, err), err);
    CHECK_OK(model_runner_create(lay2->nn, 8, NBRDF_NN_INFER, &r2, err), err);
    CHECK_OK(model_layering_eval(lay, &r1, N, lat, lat2, a, s, o1, err), err);
    CHECK_OK(model_layering_eval(lay2, &r2, N, lat, lat2, a, s, o2, err), err);
    CHECK(!memcmp(o1, o2, sizeof o1));
    model_runner_destroy(&r1);
    model_runner_destroy(&r2);
  }
  /* A layering file is not a sampler file. */
  model_sampler *wrong = NULL;
  CHECK_OK(nn_st_open(path_in(dir, "lay.safetensors"), &r, err), err);
  if (r) CHECK_FAILS(model_sampler_read(r, &wrong, err), NBRDF_ERR_MISMATCH, err, "nbrdf.network");
  nn_st_close(r);
  model_layering_destroy(lay);
  model_layering_destroy(lay2);

  model_sampler *smp = NULL, *smp2 = NULL;
  CHECK_OK(model_sampler_create("default", 32, 13, &smp, err), err);
  CHECK_OK(model_sampler_save(smp, path_in(dir, "smp.safetensors"), NULL, err), err);
  CHECK_OK(nn_st_open(path_in(dir, "smp.safetensors"), &r, err), err);
  if (r) CHECK_OK(model_sampler_read(r, &smp2, err), err);
  nn_st_close(r);
  if (smp && smp2) {
    model_runner r1, r2;
    float s1[N], w1[N], s2[N], w2[N];
    CHECK_OK(model_runner_create(smp->nn, 8, NBRDF_NN_INFER, &r1, err), err);
    CHECK_OK(model_runner_create(smp2->nn, 8, NBRDF_NN_INFER, &r2, err), err);
    CHECK_OK(model_sampler_eval(smp, &r1, N, lat, s1, w1, err), err);
    CHECK_OK(model_sampler_eval(smp2, &r2, N, lat, s2, w2, err), err);
    CHECK(!memcmp(s1, s2, sizeof s1) && !memcmp(w1, w2, sizeof w1));
    model_runner_destroy(&r1);
    model_runner_destroy(&r2);
  }
  model_sampler_destroy(smp);
  model_sampler_destroy(smp2);
}

/* Outputs of every public call on two models must agree bit for bit. */
static void check_same_outputs(const nbrdf_model *m1, const nbrdf_model *m2) {
  nbrdf_error err_ = {0}, *err = &err_;
  core_rng rng;
  core_rng_init(&rng, 2, 0);
  enum { N = 20 };
  static float lat[N * 3 * 32], wi[N * 3], wo[N * 3], f1[N * 3], f2[N * 3];
  static float top[N * 32], bottom[N * 32], o1[N * 32], o2[N * 32];
  float a[N], s[N], sg1[N], w1[N], sg2[N], w2[N];
  float alpha[N], eta[N], r0[N];
  for (int i = 0; i < N * 3 * 32; i++)
    lat[i] = (float)core_rng_normal(&rng);
  random_queries(&rng, N, wi, wo);
  for (int k = 0; k < N; k++) {
    alpha[k] = (float)(0.01 + 0.99 * core_rng_uniform(&rng));
    eta[k] = (float)(1.05 + 0.95 * core_rng_uniform(&rng));
    r0[k] = (float)core_rng_uniform(&rng);
    a[k] = (float)core_rng_uniform(&rng), s[k] = (float)(5.0 * core_rng_uniform(&rng));
  }
  CHECK_OK(nbrdf_model_decode(m1, N, 3, lat, wi, wo, f1, err), err);
  CHECK_OK(nbrdf_model_decode(m2, N, 3, lat, wi, wo, f2, err), err);
  CHECK(!memcmp(f1, f2, sizeof f1));
  for (int i = 0; i < N * 3; i++)
    CHECK(isfinite(f1[i]) && f1[i] >= 0.0f);
  CHECK_OK(nbrdf_model_base_latents(m1, NBRDF_BASE_DIELECTRIC, N, alpha, eta, NBRDF_RANGE_REFUSE,
                                    top, NULL, err),
           err);
  CHECK_OK(nbrdf_model_base_latents(m2, NBRDF_BASE_CONDUCTOR, N, alpha, r0, NBRDF_RANGE_REFUSE,
                                    bottom, NULL, err),
           err);
  CHECK_OK(nbrdf_model_layer(m1, N, top, bottom, a, s, o1, err), err);
  CHECK_OK(nbrdf_model_layer(m2, N, top, bottom, a, s, o2, err), err);
  CHECK(!memcmp(o1, o2, sizeof o1));
  CHECK_OK(nbrdf_model_proxy_params(m1, N, o1, sg1, w1, err), err);
  CHECK_OK(nbrdf_model_proxy_params(m2, N, o2, sg2, w2, err), err);
  CHECK(!memcmp(sg1, sg2, sizeof sg1) && !memcmp(w1, w2, sizeof w1));
  for (int k = 0; k < N; k++)
    CHECK(sg1[k] > 0.0f && w1[k] >= 0.0f && w1[k] <= 1.0f);
}

static void test_bundle_round_trip(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  char a[1024], b[1024], c[1024], d[1024];
  snprintf(a, sizeof a, "%s", path_in(testing_tmpdir(), "bundle-a"));
  snprintf(b, sizeof b, "%s", path_in(testing_tmpdir(), "b/c/bundle-b"));
  snprintf(c, sizeof c, "%s", path_in(testing_tmpdir(), "bundle-c"));
  snprintf(d, sizeof d, "%s", path_in(testing_tmpdir(), "bundle-d"));
  CHECK_OK(model_bundle_init_random(a, "test-a", 5, "small", err), err);
  CHECK_OK(model_bundle_init_random(b, "test-b", 5, "small", err), err);
  CHECK_OK(model_bundle_init_random(c, "test-c", 6, "small", err), err);
  nbrdf_model *ma = NULL, *mb = NULL, *mc = NULL;
  CHECK_OK(nbrdf_model_load(a, &ma, err), err);
  CHECK_OK(nbrdf_model_load(b, &mb, err), err);
  CHECK_OK(nbrdf_model_load(c, &mc, err), err);
  if (!ma || !mb || !mc) return;
  CHECK(!strcmp(nbrdf_model_name(ma), "test-a"));
  CHECK(!nbrdf_model_is_trained(ma));
  CHECK(nbrdf_model_latent_dim(ma) == 32);
  CHECK(strlen(nbrdf_model_checksum(ma)) == 16);
  /* Same seed: same bytes, same checksum, whatever the name; another seed: another checksum. */
  CHECK(!strcmp(nbrdf_model_checksum(ma), nbrdf_model_checksum(mb)));
  CHECK(strcmp(nbrdf_model_checksum(ma), nbrdf_model_checksum(mc)) != 0);
  CHECK(nbrdf_model_decoder_macs(ma) == 5344);
  check_same_outputs(ma, mb);

  /* Saving a loaded model again reproduces the files: same checksum. */
  model_bundle_parts parts = {.name = "test-d",
                              .trained = 0,
                              .seed = 5,
                              .decoder = ma->decoder,
                              .layering = ma->layering,
                              .sampler = ma->sampler,
                              .tables = {&ma->tables[0], &ma->tables[1]}};
  uint64_t sum = 0;
  CHECK_OK(model_bundle_save(d, &parts, &sum, err), err);
  nbrdf_model *md = NULL;
  CHECK_OK(nbrdf_model_load(d, &md, err), err);
  if (md) {
    CHECK(!strcmp(nbrdf_model_checksum(md), nbrdf_model_checksum(ma)));
    check_same_outputs(ma, md);
  }
  char hex[17];
  snprintf(hex, sizeof hex, "%016llx", (unsigned long long)sum);
  CHECK(!strcmp(hex, nbrdf_model_checksum(ma)));
  nbrdf_model_destroy(md);
  nbrdf_model_destroy(ma);
  nbrdf_model_destroy(mb);
  nbrdf_model_destroy(mc);
}

static void test_bundle_refusals(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  const char *tmp = testing_tmpdir();
  char dir[1024];
  snprintf(dir, sizeof dir, "%s", path_in(tmp, "bad"));
  nbrdf_model *m = NULL;
  CHECK_FAILS(nbrdf_model_load(dir, &m, err), NBRDF_ERR_IO, err, "bad/model.json");
  CHECK_OK(model_bundle_init_random(dir, "bad", 9, "small", err), err);

  /* A missing file is named. */
  rename(path_in(dir, "sampler.safetensors"), path_in(tmp, "sampler.keep"));
  CHECK_FAILS(nbrdf_model_load(dir, &m, err), NBRDF_ERR_IO, err, "sampler.safetensors");
  rename(path_in(tmp, "sampler.keep"), path_in(dir, "sampler.safetensors"));
  CHECK_OK(nbrdf_model_load(dir, &m, err), err);
  nbrdf_model_destroy(m);
  m = NULL;

  /* A layering network of another latent dimension. */
  copy_file(path_in(dir, "layering.safetensors"), path_in(tmp, "layering.keep"));
  model_layering *lay16 = NULL;
  CHECK_OK(model_layering_create("small", 16, 1, &lay16, err), err);
  CHECK_OK(model_layering_save(lay16, path_in(dir, "layering.safetensors"), NULL, err), err);
  model_layering_destroy(lay16);
  CHECK_FAILS(nbrdf_model_load(dir, &m, err), NBRDF_ERR_MISMATCH, err, "layering.safetensors");
  CHECK(strstr(err->message, "latent dimension 16") != NULL);

  /* A decoder replaced by another of the same shape: the checksum in model.json catches it. */
  copy_file(path_in(tmp, "layering.keep"), path_in(dir, "layering.safetensors"));
  model_decoder_config cfg;
  model_decoder *other = NULL;
  CHECK_OK(model_decoder_preset("small", 32, &cfg, err), err);
  CHECK_OK(model_decoder_create(&cfg, 12345, &other, err), err);
  copy_file(path_in(dir, "decoder.safetensors"), path_in(tmp, "decoder.keep"));
  CHECK_OK(model_decoder_save(other, path_in(dir, "decoder.safetensors"), NULL, err), err);
  model_decoder_destroy(other);
  CHECK_FAILS(nbrdf_model_load(dir, &m, err), NBRDF_ERR_MISMATCH, err, "model.json: checksum");

  /* A truncated decoder. */
  char *bytes = NULL;
  size_t size = 0;
  CHECK_OK(model_read_file(path_in(tmp, "decoder.keep"), UINT64_MAX, &bytes, &size, err), err);
  FILE *fp = fopen(path_in(dir, "decoder.safetensors"), "wb");
  if (fp && bytes) {
    fwrite(bytes, 1, size / 2, fp);
    fclose(fp);
  }
  free(bytes);
  CHECK_FAILS(nbrdf_model_load(dir, &m, err), NBRDF_ERR_FORMAT, err, "decoder.safetensors");
  copy_file(path_in(tmp, "decoder.keep"), path_in(dir, "decoder.safetensors"));

  /* A sampler file where the base tables belong. */
  copy_file(path_in(dir, "base_tables.safetensors"), path_in(tmp, "tables.keep"));
  copy_file(path_in(dir, "sampler.safetensors"), path_in(dir, "base_tables.safetensors"));
  CHECK_FAILS(nbrdf_model_load(dir, &m, err), NBRDF_ERR_FORMAT, err, "base_tables.safetensors");
  copy_file(path_in(tmp, "tables.keep"), path_in(dir, "base_tables.safetensors"));

  /* A model.json that is not one. */
  CHECK_OK(model_write_text_file(dir, "model.json", "{\"format\": \"nbrdf-model\", \"version\": 1}",
                                 err),
           err);
  CHECK_FAILS(nbrdf_model_load(dir, &m, err), NBRDF_ERR_FORMAT, err, "model.json: \"name\"");
  CHECK_OK(model_write_text_file(dir, "model.json", "not json", err), err);
  CHECK_FAILS(nbrdf_model_load(dir, &m, err), NBRDF_ERR_FORMAT, err, "model.json");
  CHECK(m == NULL);
}

static void test_public_calls(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  char dir[1024];
  snprintf(dir, sizeof dir, "%s", path_in(testing_tmpdir(), "pub"));
  CHECK_OK(model_bundle_init_random(dir, "pub", 3, "small", err), err);
  nbrdf_model *m = NULL;
  CHECK_OK(nbrdf_model_load(dir, &m, err), err);
  if (!m) return;
  float lat[32] = {0}, f[1], out[32];
  float wi[3] = {0, 0, 1}, below[3] = {0.6f, 0, -0.8f}, longer[3] = {0, 0, 1.1f},
        nan3[3] = {NAN, 0, 1};
  CHECK_FAILS(nbrdf_model_decode(m, 1, 1, lat, wi, below, f, err), NBRDF_ERR_ARGUMENT, err,
              "wo of query 0 is at or below");
  CHECK_FAILS(nbrdf_model_decode(m, 1, 1, lat, longer, wi, f, err), NBRDF_ERR_ARGUMENT, err,
              "not a unit");
  CHECK_FAILS(nbrdf_model_decode(m, 1, 1, lat, nan3, wi, f, err), NBRDF_ERR_ARGUMENT, err,
              "not finite");
  lat[3] = INFINITY;
  CHECK_FAILS(nbrdf_model_decode(m, 1, 1, lat, wi, wi, f, err), NBRDF_ERR_ARGUMENT, err, "value 3");
  lat[3] = 0.0f;
  float bad_a = 1.5f, ok_a = 0.5f, neg_s = -1.0f, ok_s = 2.0f;
  CHECK_FAILS(nbrdf_model_layer(m, 1, lat, lat, &bad_a, &ok_s, out, err), NBRDF_ERR_ARGUMENT, err,
              "albedo");
  CHECK_FAILS(nbrdf_model_layer(m, 1, lat, lat, &ok_a, &neg_s, out, err), NBRDF_ERR_ARGUMENT, err,
              "sigma_t");
  /* Base tables: exact at grid nodes, clamped with a flag or refused outside. */
  int n0, n1;
  const float *ax0, *ax1;
  nbrdf_model_base_grid(m, NBRDF_BASE_CONDUCTOR, &n0, &ax0, &n1, &ax1);
  CHECK(n0 >= 2 && n1 >= 2 && ax0[0] == 0.01f && ax1[n1 - 1] == 1.0f);
  float p0 = ax0[2], p1 = ax1[1], far = 7.0f;
  unsigned char flag = 0;
  CHECK_OK(nbrdf_model_base_latents(m, NBRDF_BASE_CONDUCTOR, 1, &p0, &p1, NBRDF_RANGE_REFUSE, out,
                                    &flag, err),
           err);
  CHECK(!memcmp(out, m->tables[1].latents + (2 * n1 + 1) * 32, sizeof out));
  CHECK_OK(nbrdf_model_base_latents(m, NBRDF_BASE_CONDUCTOR, 1, &p0, &far, NBRDF_RANGE_CLAMP, out,
                                    &flag, err),
           err);
  CHECK(flag == NBRDF_CLAMPED_PARAM1);
  CHECK_FAILS(nbrdf_model_base_latents(m, NBRDF_BASE_DIELECTRIC, 1, &p0, &far, NBRDF_RANGE_REFUSE,
                                       out, &flag, err),
              NBRDF_ERR_ARGUMENT, err, "eta = 7");

  /* Projection through the public call: samples decoded from a table latent
   * are fitted far better than by the zero latent the fit starts from. */
  enum { NB = 2, PER = 256 };
  static float swi[NB * PER * 3], swo[NB * PER * 3], sf[NB * PER], src[NB * PER * 32];
  size_t offsets[NB + 1] = {0, PER, 2 * PER};
  core_rng rng;
  core_rng_init(&rng, 4, 0);
  random_queries(&rng, NB * PER, swi, swo);
  float pa[NB] = {0.05f, 0.5f}, pr[NB] = {0.9f, 0.3f};
  float z[NB * 32], zero_loss_lat[NB * 32] = {0};
  CHECK_OK(nbrdf_model_base_latents(m, NBRDF_BASE_CONDUCTOR, NB, pa, pr, NBRDF_RANGE_REFUSE, z,
                                    NULL, err),
           err);
  for (int k = 0; k < NB * PER; k++)
    memcpy(src + 32 * k, z + 32 * (k / PER), 32 * sizeof(float));
  CHECK_OK(nbrdf_model_decode(m, NB * PER, 1, src, swi, swo, sf, err), err);
  nbrdf_project_options po = NBRDF_PROJECT_OPTIONS_DEFAULT;
  po.steps = 0;
  double before[NB], after[NB];
  CHECK_OK(nbrdf_model_project(m, NB, offsets, swi, swo, sf, &po, zero_loss_lat, before, err), err);
  po.steps = 300;
  float fitted[NB * 32];
  CHECK_OK(nbrdf_model_project(m, NB, offsets, swi, swo, sf, &po, fitted, after, err), err);
  for (int b = 0; b < NB; b++)
    CHECK_MSG(after[b] < 0.2 * before[b], "BRDF %d: projection loss %.4g -> %.4g", b, before[b],
              after[b]);
  sf[5] = -1.0f;
  CHECK_FAILS(nbrdf_model_project(m, NB, offsets, swi, swo, sf, &po, fitted, after, err),
              NBRDF_ERR_ARGUMENT, err, "sample 5");
  nbrdf_model_destroy(m);
}

int main(void) {
  RUN(test_network_round_trips);
  RUN(test_bundle_round_trip);
  RUN(test_bundle_refusals);
  RUN(test_public_calls);
  return testing_finish();
}
