#include "bake/bake_compact.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_select.h"
#include "core/error.h"
#include "core/linalg.h"
#include "core/rng.h"
#include "model/autodecoder.h"
#include "model/bundle.h"
#include "nbrdf/model.h"
#include "train/trainer.h"

void bake_compact_free(bake_compact *c) {
  free(c->mean);
  free(c->basis);
  free(c->project);
  model_decoder_destroy(c->student);
  memset(c, 0, sizeof *c);
}

nbrdf_status bake_compact_basis(const float *z, size_t n, int D, int K, bake_compact *c,
                                nbrdf_error *err) {
  memset(c, 0, sizeof *c);
  if (K < 1 || K > D || n == 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "compact: %d coordinates of %zu latents of %d", K,
                      n, D);
  c->dim = K, c->work_dim = D;
  c->mean = calloc((size_t)D, sizeof(float));
  c->basis = calloc((size_t)D * K, sizeof(float));
  c->project = calloc((size_t)D * K, sizeof(float));
  double *cov = calloc((size_t)D * D * 2 + 2 * D, sizeof(double));
  if (!c->mean || !c->basis || !c->project || !cov) {
    free(cov);
    bake_compact_free(c);
    return core_fail(err, NBRDF_ERR_MEMORY, "compact: out of memory");
  }
  double *vec = cov + (size_t)D * D, *ev = vec + (size_t)D * D, *mean = ev + D;
  for (size_t k = 0; k < n; k++)
    for (int d = 0; d < D; d++)
      mean[d] += z[k * D + d];
  for (int d = 0; d < D; d++)
    mean[d] /= (double)n, c->mean[d] = (float)mean[d];
  for (size_t k = 0; k < n; k++)
    for (int i = 0; i < D; i++) {
      double zi = z[k * D + i] - mean[i];
      for (int j = 0; j <= i; j++)
        cov[i * D + j] += zi * (z[k * D + j] - mean[j]);
    }
  for (int i = 0; i < D; i++)
    for (int j = 0; j <= i; j++)
      cov[j * D + i] = cov[i * D + j] /= (double)n;
  core_linalg_symmetric_eigen(cov, D, ev, vec);
  double total = 0.0, kept = 0.0;
  for (int i = 0; i < D; i++)
    total += ev[i] > 0 ? ev[i] : 0.0;
  /* The K largest, in order; each eigenvector's sign fixed by its largest
   * component so that the basis is a function of the latents alone. */
  int used[512] = {0};
  for (int j = 0; j < K; j++) {
    int best = -1;
    for (int i = 0; i < D; i++)
      if (!used[i] && (best < 0 || ev[i] > ev[best])) best = i;
    used[best] = 1;
    int big = 0;
    for (int d = 1; d < D; d++)
      if (fabs(vec[d * D + best]) > fabs(vec[big * D + best])) big = d;
    double sign = vec[big * D + best] < 0 ? -1.0 : 1.0;
    double lam = ev[best] > 0 ? ev[best] : 0.0;
    kept += lam;
    /* A direction without variance (a constant scene) keeps scale 1. */
    double s = lam > 1e-12 ? sqrt(lam) : 1.0;
    for (int d = 0; d < D; d++) {
      double u = sign * vec[d * D + best];
      c->basis[d * K + j] = (float)(u * s);
      c->project[j * D + d] = (float)(u / s);
    }
  }
  c->kept = total > 0 ? kept / total : 1.0;
  free(cov);
  return NBRDF_OK;
}

static void bake_compact_reduce_centred(const bake_compact *c, const float *zc, float *coords) {
  for (int j = 0; j < c->dim; j++) {
    double s = 0.0;
    for (int d = 0; d < c->work_dim; d++)
      s += (double)c->project[j * c->work_dim + d] * zc[d];
    coords[j] = (float)s;
  }
}

void bake_compact_reduce(const bake_compact *c, const float *z, float *coords) {
  for (int j = 0; j < c->dim; j++) {
    double s = 0.0;
    for (int d = 0; d < c->work_dim; d++)
      s += (double)c->project[j * c->work_dim + d] * (z[d] - c->mean[d]);
    coords[j] = (float)s;
  }
}

void bake_compact_expand(const bake_compact *c, const float *coords, float *z) {
  for (int d = 0; d < c->work_dim; d++) {
    double s = c->mean[d];
    for (int j = 0; j < c->dim; j++)
      s += (double)c->basis[d * c->dim + j] * coords[j];
    z[d] = (float)s;
  }
}

/* The teacher's rows of tuple k: the directions of its nearest fitted
 * tuple's ground truth (where the family's lobes are), then PROXY_ROWS more
 * whose ωo the tuple's own pdf proxy draws around its lobe (its incident
 * directions taken from the same rows), then SPREAD_ROWS, all with the
 * specialised decoder's values there. `z` holds each tuple's latent, sigma and w (D + 2). */
#define PROXY_ROWS 1024
#define PROJECTION_LR 2e-3f
/* ... and SPREAD_ROWS with ωi uniform over the hemisphere, grazing included
 * (ωo half from the proxy, half uniform): a small network extrapolates
 * wildly where it saw nothing, and a renderer asks there. */
#define SPREAD_ROWS 1024

static void uniform_direction(core_rng *rng, double w[3]) {
  double z = 1e-3 + (1.0 - 1e-3) * core_rng_uniform(rng), phi = 2.0 * M_PI * core_rng_uniform(rng);
  double s = sqrt(1.0 - z * z);
  w[0] = s * cos(phi), w[1] = s * sin(phi), w[2] = z;
}
static nbrdf_status teacher_rows(const model_decoder *teacher, const bake_tuple *fit, size_t n_fit,
                                 const train_samples *truth, const bake_tuple *t, size_t n,
                                 const float *z, const float *lo, const float *hi, uint64_t seed,
                                 train_samples *out, nbrdf_error *err) {
  memset(out, 0, sizeof *out);
  const int D = teacher->cfg.latent_dim;
  size_t *near = malloc(sizeof *near * (n ? n : 1)), rows = 0;
  if (!near) return core_fail(err, NBRDF_ERR_MEMORY, "compact: out of memory");
  for (size_t k = 0; k < n; k++) {
    float best = INFINITY;
    near[k] = 0;
    for (size_t j = 0; j < n_fit; j++) {
      float d = bake_tuple_distance2(&t[k], &fit[j], lo, hi);
      if (d < best) best = d, near[k] = j;
    }
    rows += truth->offsets[near[k] + 1] - truth->offsets[near[k]] + PROXY_ROWS + SPREAD_ROWS;
  }
  out->n_brdfs = n, out->n_rows = rows;
  out->offsets = malloc(sizeof(size_t) * (n + 1));
  out->wi = malloc(sizeof(float) * 3 * (rows ? rows : 1));
  out->wo = malloc(sizeof(float) * 3 * (rows ? rows : 1));
  out->f = malloc(sizeof(float) * (rows ? rows : 1));
  float *lat = malloc(sizeof(float) * (rows ? rows : 1) * D);
  model_runner run = {0};
  nbrdf_status st = NBRDF_OK;
  if (!out->offsets || !out->wi || !out->wo || !out->f || !lat)
    st = core_fail(err, NBRDF_ERR_MEMORY, "compact: out of memory for %zu teacher rows", rows);
  size_t r = 0;
  for (size_t k = 0; st == NBRDF_OK && k < n; k++) {
    out->offsets[k] = r;
    size_t a = truth->offsets[near[k]], b = truth->offsets[near[k] + 1];
    memcpy(out->wi + 3 * r, truth->wi + 3 * a, sizeof(float) * 3 * (b - a));
    memcpy(out->wo + 3 * r, truth->wo + 3 * a, sizeof(float) * 3 * (b - a));
    size_t r0 = r;
    r += b - a;
    core_rng rng;
    core_rng_init(&rng, seed, k);
    const float *zk = z + k * (size_t)(D + 2);
    for (int q = 0; q < PROXY_ROWS + SPREAD_ROWS; q++, r++) {
      double wid[3], u[3], wo[3], pdf;
      if (q < PROXY_ROWS) {
        const float *wi = truth->wi + 3 * (a + (size_t)q % (b - a));
        wid[0] = wi[0], wid[1] = wi[1], wid[2] = wi[2];
      } else
        uniform_direction(&rng, wid);
      int ok = 0;
      if (q < PROXY_ROWS || q % 2)
        for (int tries = 0; !ok && tries < 16; tries++) {
          for (int i = 0; i < 3; i++)
            u[i] = core_rng_uniform(&rng);
          ok = nbrdf_proxy_sample(zk[D], zk[D + 1], wid, u, wo, &pdf) && wo[2] > 1e-4;
        }
      if (!ok) uniform_direction(&rng, wo);
      for (int i = 0; i < 3; i++)
        out->wi[3 * r + i] = (float)wid[i], out->wo[3 * r + i] = (float)wo[i];
    }
    for (size_t i = r0; i < r; i++)
      memcpy(lat + i * D, zk, sizeof(float) * D);
  }
  if (st == NBRDF_OK) {
    out->offsets[n] = r;
    st = model_runner_create(teacher->nn, 4096, NBRDF_NN_INFER, &run, err);
  }
  if (st == NBRDF_OK)
    st = model_decoder_eval(teacher, &run, rows, 1, lat, out->wi, out->wo, out->f, err);
  model_runner_destroy(&run);
  free(lat);
  free(near);
  if (st != NBRDF_OK) train_samples_free(out);
  return st;
}

typedef struct distil {
  model_fit *fit;
  model_samples ms;
  size_t n;
  int K, D;
  const float *zc; /* [n x D] latents minus the mean */
  float *P, *gP;   /* [K x D] the projection and its gradient */
  float *coords;   /* [n x K] P zc, the fit's latents */
} distil;

/* The projection learns with the student: coords = P zc, so dL/dP is the sum
 * over BRDFs of dL/dcoords zcᵀ (the fit's latent gradient). */
static nbrdf_status distil_gradient(void *user, int64_t step, double *loss, nbrdf_error *err) {
  distil *d = user;
  for (size_t b = 0; b < d->n; b++)
    for (int j = 0; j < d->K; j++) {
      double s = 0.0;
      for (int i = 0; i < d->D; i++)
        s += (double)d->P[j * d->D + i] * d->zc[b * d->D + i];
      d->coords[b * d->K + j] = (float)s;
    }
  nbrdf_status st = model_fit_gradient(d->fit, &d->ms, step, loss, err);
  if (st != NBRDF_OK) return st;
  const float *gl = model_fit_grad_latent(d->fit);
  memset(d->gP, 0, sizeof(float) * d->K * d->D);
  for (size_t b = 0; b < d->n; b++)
    for (int j = 0; j < d->K; j++) {
      float g = gl[b * d->K + j];
      for (int i = 0; i < d->D; i++)
        d->gP[j * d->D + i] += g * d->zc[b * d->D + i];
    }
  return NBRDF_OK;
}

/* After the projection learned: the basis that best reconstructs the scene's
 * latents from their coordinates (least squares, B = Zc Cᵀ (C Cᵀ)⁻¹; the
 * proxy of a mip texel is predicted from mean + B c) and the share of their
 * variance it keeps. A singular C Cᵀ (a constant scene) keeps the basis. */
static void refit_basis(bake_compact *c, const float *zc, size_t n) {
  const int K = c->dim, D = c->work_dim;
  double g[BAKE_COMPACT_MAX_DIM * BAKE_COMPACT_MAX_DIM] = {0};
  double gi[BAKE_COMPACT_MAX_DIM * BAKE_COMPACT_MAX_DIM];
  double *m = calloc((size_t)D * K, sizeof(double));
  float *cb = malloc(sizeof(float) * K * (n ? n : 1));
  if (!m || !cb) {
    free(m), free(cb);
    return;
  }
  for (size_t b = 0; b < n; b++)
    bake_compact_reduce_centred(c, zc + b * D, cb + b * K);
  for (size_t b = 0; b < n; b++)
    for (int j = 0; j < K; j++) {
      for (int k = 0; k < K; k++)
        g[j * K + k] += (double)cb[b * K + j] * cb[b * K + k];
      for (int i = 0; i < D; i++)
        m[i * K + j] += (double)zc[b * D + i] * cb[b * K + j];
    }
  if (core_linalg_invert(g, K, gi)) {
    double res = 0.0, tot = 0.0;
    for (int i = 0; i < D; i++)
      for (int k = 0; k < K; k++) {
        double v = 0.0;
        for (int j = 0; j < K; j++)
          v += m[i * K + j] * gi[j * K + k];
        c->basis[i * K + k] = (float)v;
      }
    for (size_t b = 0; b < n; b++)
      for (int i = 0; i < D; i++) {
        double v = 0.0;
        for (int k = 0; k < K; k++)
          v += (double)c->basis[i * K + k] * cb[b * K + k];
        res += (zc[b * D + i] - v) * (zc[b * D + i] - v), tot += (double)zc[b * D + i] * zc[b * D + i];
      }
    c->kept = tot > 0.0 ? 1.0 - res / tot : 1.0;
  }
  free(m), free(cb);
}

nbrdf_status bake_compact_build(const nbrdf_model *model, const bake_correction *corr,
                                const bake_tuple *fit, size_t n_fit, const train_samples *truth,
                                const bake_tuple *scene, size_t n_scene, int dim,
                                const bake_compact_settings *s, bake_compact *c,
                                nbrdf_error *err) {
  memset(c, 0, sizeof *c);
  const model_decoder *teacher = bake_correction_decoder(corr, model);
  const int D = nbrdf_model_latent_dim(model);
  const size_t n_all = n_fit + n_scene;
  float lo[NBRDF_BAKE_PARAM_COUNT], hi[NBRDF_BAKE_PARAM_COUNT];
  model_material_ranges(model, lo, hi);
  /* Specialised latents: the fitted tuples', then the scene's (network + carried correction). */
  bake_tuple *all = malloc(sizeof *all * (n_all ? n_all : 1));
  float *net = malloc(sizeof(float) * (n_all ? n_all : 1) * (D + 2));
  float *z = malloc(sizeof(float) * (n_all ? n_all : 1) * D);
  float *coords = malloc(sizeof(float) * (n_all ? n_all : 1) * dim);
  train_samples teach = {0};
  nbrdf_status st = NBRDF_OK;
  if (!all || !net || !z || !coords)
    st = core_fail(err, NBRDF_ERR_MEMORY, "compact: out of memory");
  if (st == NBRDF_OK) {
    memcpy(all, fit, sizeof *fit * n_fit);
    memcpy(all + n_fit, scene, sizeof *scene * n_scene);
    st = bake_tuples_evaluate(model, all, NULL, n_all, net, err);
  }
  if (st == NBRDF_OK) {
    bake_correct_latents(corr, all, NULL, n_all, net, (size_t)D + 2);
    for (size_t k = 0; k < n_all; k++)
      memcpy(z + k * D, net + k * (D + 2), sizeof(float) * D);
    st = bake_compact_basis(z, n_all, D, dim, c, err);
  }
  for (size_t k = 0; st == NBRDF_OK && k < n_all; k++)
    bake_compact_reduce(c, z + k * D, coords + k * dim);
  if (st == NBRDF_OK)
    st = teacher_rows(teacher, fit, n_fit, truth, scene, n_scene, net + n_fit * (D + 2), lo, hi,
                      s->seed + 5, &teach, err);
  /* One sample set: the fitted tuples' truth, then the scene's teacher rows. */
  size_t *offsets = NULL;
  float *wi = NULL, *wo = NULL, *f = NULL;
  if (st == NBRDF_OK) {
    size_t rows = truth->n_rows + teach.n_rows;
    offsets = malloc(sizeof *offsets * (n_all + 1));
    wi = malloc(sizeof(float) * 3 * rows), wo = malloc(sizeof(float) * 3 * rows);
    f = malloc(sizeof(float) * rows);
    if (!offsets || !wi || !wo || !f)
      st = core_fail(err, NBRDF_ERR_MEMORY, "compact: out of memory for %zu rows", rows);
  }
  if (st == NBRDF_OK) {
    memcpy(offsets, truth->offsets, sizeof *offsets * (n_fit + 1));
    for (size_t k = 1; k <= n_scene; k++)
      offsets[n_fit + k] = truth->n_rows + teach.offsets[k];
    memcpy(wi, truth->wi, sizeof(float) * 3 * truth->n_rows);
    memcpy(wi + 3 * truth->n_rows, teach.wi, sizeof(float) * 3 * teach.n_rows);
    memcpy(wo, truth->wo, sizeof(float) * 3 * truth->n_rows);
    memcpy(wo + 3 * truth->n_rows, teach.wo, sizeof(float) * 3 * teach.n_rows);
    memcpy(f, truth->f, sizeof(float) * truth->n_rows);
    memcpy(f + truth->n_rows, teach.f, sizeof(float) * teach.n_rows);
  }
  model_decoder_config cfg;
  if (st == NBRDF_OK) st = model_decoder_compact_config(dim, s->width, &cfg, err);
  if (st == NBRDF_OK) st = model_decoder_create(&cfg, s->seed, &c->student, err);
  /* The latents minus the mean, for the projection's gradient. */
  float *zc = st == NBRDF_OK ? malloc(sizeof(float) * n_all * D) : NULL;
  float *gP = st == NBRDF_OK ? malloc(sizeof(float) * dim * D) : NULL;
  if (st == NBRDF_OK && (!zc || !gP)) st = core_fail(err, NBRDF_ERR_MEMORY, "compact: out of memory");
  for (size_t k = 0; st == NBRDF_OK && k < n_all; k++)
    for (int i = 0; i < D; i++)
      zc[k * D + i] = z[k * D + i] - c->mean[i];
  distil d = {NULL, {n_all, offsets, wi, wo, f, NULL}, n_all, dim, D, zc, c->project, gP, coords};
  model_fit_options o = MODEL_FIT_OPTIONS_DEFAULT;
  o.rows_per_brdf = s->rows;
  o.seed = s->seed + 2;
  o.lr_latent = 0.0f;
  /* Measured on a constant sharp coat (10,210 steps): 2e-3 11.8 %, 5e-3 7.0 %, 1e-2 5.8 %,
   * 2e-2 3.8 %, 4e-2 4.9 %, 8e-2 4.2 % held-out lobe error: a small network wants a high rate. */
  o.lr_weights = 2e-2f;
  if (st == NBRDF_OK) st = model_fit_create(c->student, n_all, coords, &o, &d.fit, err);
  if (st == NBRDF_OK) {
    /* The student and the projection learn together, starting from the
     * principal one; every texel's coordinates are then that one linear map
     * of its latent. */
    int decay = s->steps / 3 > 0 ? s->steps / 3 : 0;
    trainer_group g[2] = {{"decoder.params", "adam.weights.m", "adam.weights.v",
                           nn_params(c->student->nn), model_fit_grad_weights(d.fit),
                           nn_param_count(c->student->nn), o.lr_weights, decay, 0.3f},
                          {"projection", "adam.projection.m", "adam.projection.v", c->project, gP,
                           (size_t)dim * D, PROJECTION_LR, decay, 0.3f}};
    trainer_options to = TRAINER_OPTIONS_DEFAULT;
    to.steps = s->steps;
    to.stage = "distil";
    to.cancel = s->cancel;
    to.ticker = s->ticker;
    to.progress_total = s->steps;
    trainer_fit tf = {.user = &d, .gradient = distil_gradient};
    trainer_result r;
    st = trainer_run(&to, &tf, g, 2, NULL, 0, NULL, 0, &r, err);
    if (st == NBRDF_ERR_CANCELLED)
      st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled while distilling (step %d of %d)",
                     (int)r.steps_done, s->steps);
  }
  double *per = st == NBRDF_OK ? malloc(sizeof(double) * n_all) : NULL;
  if (st == NBRDF_OK && !per) st = core_fail(err, NBRDF_ERR_MEMORY, "compact: out of memory");
  double mean;
  if (st == NBRDF_OK) {
    double lf;
    st = distil_gradient(&d, 0, &lf, err); /* coords of the final projection */
  }
  if (st == NBRDF_OK) st = model_fit_eval_loss(d.fit, &d.ms, per, &mean, err);
  if (st == NBRDF_OK) refit_basis(c, zc, n_all);
  if (st == NBRDF_OK) {
    double a = 0.0, b = 0.0;
    for (size_t k = 0; k < n_all; k++)
      *(k < n_fit ? &a : &b) += per[k];
    c->loss_truth = n_fit ? a / n_fit : 0.0;
    c->loss_teacher = n_scene ? b / n_scene : 0.0;
  }
  free(per);
  model_fit_destroy(d.fit);
  free(offsets), free(wi), free(wo), free(f);
  train_samples_free(&teach);
  free(all), free(net), free(z), free(coords), free(zc), free(gP);
  if (st != NBRDF_OK) bake_compact_free(c);
  return st;
}

void bake_compact_texels(const bake_compact *c, const texture_latent_layout *work, const float *in,
                         const texture_latent_layout *out_layout, float *out, size_t n) {
  const int C = texture_latent_colours(work);
  const int fin = texture_latent_channel_count(work),
            fout = texture_latent_channel_count(out_layout);
  float z[NBRDF_LATENT_MAX_DIM], coords[BAKE_COMPACT_MAX_DIM];
  for (size_t i = 0; i < n; i++) {
    const float *t = in + i * fin;
    float *o = out + i * fout;
    for (int ch = 0; ch < C; ch++) {
      for (int d = 0; d < work->latent_dim; d++)
        z[d] = t[texture_latent_index_latent(work, ch, d)];
      bake_compact_reduce(c, z, coords);
      for (int j = 0; j < c->dim; j++)
        o[texture_latent_index_latent(out_layout, ch, j)] = coords[j];
      if (work->proxy && out_layout->proxy) {
        o[texture_latent_index_sigma(out_layout, ch)] = t[texture_latent_index_sigma(work, ch)];
        o[texture_latent_index_w(out_layout, ch)] = t[texture_latent_index_w(work, ch)];
      }
    }
  }
}
