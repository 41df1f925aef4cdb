/* The figures of `nbrdf evaluate` beyond the lobe error: grazing
 * lobe images (85°, 89°), the point-wise error over every image, the error at
 * the mirror direction, and the decoded directional albedo by importance
 * sampling (src/model/albedo_quad.h) against nbrdf_brdf_albedo.
 *
 * The lobe error sums |f̂ − f| over whole images up to 80°, so a peak three
 * times too high at 85° hides behind a right background; these figures are
 * where an over-bright rim or a firefly shows. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error.h"
#include "core/progress.h"
#include "core/rng.h"
#include "eval/evaluate.h"
#include "lobe/lobe.h"
#include "model/albedo_quad.h"
#include "model/bundle.h"
#include "nn/safetensors.h"

#define IMG ((size_t)NBRDF_LOBE_RES * NBRDF_LOBE_RES)
#define PER_BRDF (NBRDF_LOBE_N_THETA * IMG)
#define PER_GRAZING (EVAL_N_GRAZING * IMG)
#define NT EVAL_N_THETA_ALL
#define EXTRA_TAG UINT64_C(0x6e62726467727a67)
/* Reference albedo: nbrdf_brdf_albedo draws (standard error ~0.3 % of ρ). */
#define REF_ALBEDO_SAMPLES (1 << 15)
/* Decoded albedo: quadrature directions per θi (standard error ~0.7 %). */
#define DECODED_ALBEDO_SAMPLES 16384
/* Point-wise error: pixels where f exceeds this fraction of the image's peak. */
#define POINTWISE_FLOOR 0.01

const double eval_theta_all_deg[NT] = {0.0, 30.0, 60.0, 80.0, 85.0, 89.0};
static const double grazing_deg[EVAL_N_GRAZING] = {85.0, 89.0};

void eval_extra_ref_free(eval_extra_ref *x) {
  free(x->images), free(x->mirror), free(x->albedo), free(x->albedo_se);
  memset(x, 0, sizeof *x);
}

static void cache_path(char *out, size_t size, eval_set set, const eval_settings *s) {
  snprintf(out, size, "%s/ref-%s-n%d-w%d-grazing.safetensors", s->cache_dir,
           eval_set_name(eval_set_reference_of(set)), s->count, s->walks);
}

static int load_cache(const char *path, const eval_settings *s, eval_extra_ref *x) {
  nn_st_reader *r = NULL;
  if (nn_st_open(path, &r, NULL) != NBRDF_OK) return 0;
  int64_t img[4] = {s->count, EVAL_N_GRAZING, NBRDF_LOBE_RES, NBRDF_LOBE_RES};
  int64_t per[2] = {s->count, NT};
  const float *a = NULL, *b = NULL, *c = NULL, *d = NULL;
  int ok = nn_st_expect(r, "images", 4, img, &a, NULL) == NBRDF_OK &&
           nn_st_expect(r, "mirror", 2, per, &b, NULL) == NBRDF_OK &&
           nn_st_expect(r, "albedo", 2, per, &c, NULL) == NBRDF_OK &&
           nn_st_expect(r, "albedo_se", 2, per, &d, NULL) == NBRDF_OK;
  if (ok) {
    for (size_t k = 0; k < (size_t)s->count * PER_GRAZING; k++)
      x->images[k] = a[k];
    for (size_t k = 0; k < (size_t)s->count * NT; k++)
      x->mirror[k] = b[k], x->albedo[k] = c[k], x->albedo_se[k] = d[k];
  }
  nn_st_close(r);
  return ok;
}

static void save_cache(const char *path, const eval_settings *s, const eval_extra_ref *x) {
  size_t ni = (size_t)s->count * PER_GRAZING, np = (size_t)s->count * NT;
  float *buf = malloc((ni + 3 * np) * sizeof *buf);
  nn_st_writer *w = NULL;
  if (buf && nn_st_writer_create(&w, NULL) == NBRDF_OK) {
    for (size_t k = 0; k < ni; k++)
      buf[k] = (float)x->images[k];
    for (size_t k = 0; k < np; k++) {
      buf[ni + k] = (float)x->mirror[k];
      buf[ni + np + k] = (float)x->albedo[k];
      buf[ni + 2 * np + k] = (float)x->albedo_se[k];
    }
    int64_t img[4] = {s->count, EVAL_N_GRAZING, NBRDF_LOBE_RES, NBRDF_LOBE_RES};
    int64_t per[2] = {s->count, NT};
    mkdir(s->cache_dir, 0777);
    /* A cache that cannot be written only costs the next run time. */
    if (nn_st_writer_add_borrowed(w, "images", 4, img, buf, NULL) == NBRDF_OK &&
        nn_st_writer_add_borrowed(w, "mirror", 2, per, buf + ni, NULL) == NBRDF_OK &&
        nn_st_writer_add_borrowed(w, "albedo", 2, per, buf + ni + np, NULL) == NBRDF_OK &&
        nn_st_writer_add_borrowed(w, "albedo_se", 2, per, buf + ni + 2 * np, NULL) == NBRDF_OK)
      (void)nn_st_writer_save(w, path, NULL, NULL);
  }
  nn_st_writer_destroy(w);
  free(buf);
}

/* f at the mirror direction ωo = (−sin θi, 0, cos θi) and ρ(θi) of one BRDF. */
static nbrdf_status point_refs(const train_params *p, uint64_t seed, int walks, double *mirror,
                               double *albedo, double *albedo_se, nbrdf_error *err) {
  nbrdf_brdf *b = NULL;
  nbrdf_status st = train_params_create(p, &b, err);
  if (st) return st;
  nbrdf_query q[NT];
  for (int t = 0; t < NT; t++) {
    double th = eval_theta_all_deg[t] * (M_PI / 180.0);
    q[t] = (nbrdf_query){{sin(th), 0.0, cos(th)}, {-sin(th), 0.0, cos(th)}};
  }
  nbrdf_eval_options o = {seed, walks, 0};
  st = nbrdf_brdf_eval(b, NT, q, &o, mirror, NULL, err);
  for (int t = 0; t < NT && !st; t++)
    st = nbrdf_brdf_albedo(b, eval_theta_all_deg[t] * (M_PI / 180.0), REF_ALBEDO_SAMPLES,
                           core_hash64(seed, (uint64_t)t), &albedo[t], &albedo_se[t], err);
  nbrdf_brdf_destroy(b);
  return st;
}

nbrdf_status eval_reference_extra(eval_set set, const eval_settings *s, eval_extra_ref *x,
                                  nbrdf_error *err) {
  memset(x, 0, sizeof *x);
  if (set == EVAL_TABLE) set = EVAL_SINGLE; /* the same BRDFs */
  size_t n = (size_t)s->count;
  x->images = malloc(n * PER_GRAZING * sizeof *x->images);
  x->mirror = malloc(n * NT * sizeof *x->mirror);
  x->albedo = malloc(n * NT * sizeof *x->albedo);
  x->albedo_se = malloc(n * NT * sizeof *x->albedo_se);
  if (!x->images || !x->mirror || !x->albedo || !x->albedo_se) {
    eval_extra_ref_free(x);
    return core_fail(err, NBRDF_ERR_MEMORY, "evaluate: out of memory");
  }
  char path[4096];
  if (s->cache_dir) {
    cache_path(path, sizeof path, set, s);
    if (load_cache(path, s, x)) return NBRDF_OK;
  }
  uint64_t family = train_heldout_seed(eval_set_heldout(set));
  char stage[64];
  snprintf(stage, sizeof stage, "%s: grazing reference", eval_set_name(set));
  core_ticker ticker;
  core_ticker_init(&ticker, s->progress, s->user, NULL);
  nbrdf_status st = NBRDF_OK;
  for (size_t i = 0; i < n && !st; i++) {
    train_params p;
    eval_set_draw(set, (uint64_t)i, &p);
    uint64_t seed = core_hash64(core_hash64(family, EXTRA_TAG), (uint64_t)i);
    st = eval_images_of(&p, seed, s->walks, NULL, EVAL_N_GRAZING, grazing_deg,
                        x->images + i * PER_GRAZING, err);
    if (!st)
      st = point_refs(&p, seed ^ 1u, s->walks, x->mirror + i * NT, x->albedo + i * NT,
                      x->albedo_se + i * NT, err);
    if (!st && core_ticker_tick(&ticker, stage, (double)(i + 1), (double)n, 1))
      st = core_fail(err, NBRDF_ERR_CANCELLED, "evaluate: cancelled");
  }
  if (st) {
    eval_extra_ref_free(x);
    return st;
  }
  if (s->cache_dir) save_cache(path, s, x);
  return NBRDF_OK;
}

nbrdf_status eval_score_extra(const nbrdf_model *model, model_decoder *dec, size_t n,
                              const float *lat, const double *ref, const eval_extra_ref *x,
                              eval_case *cases, nbrdf_error *err) {
  size_t D = (size_t)dec->cfg.latent_dim;
  model_runner runner;
  nbrdf_status st = model_runner_create(dec->nn, 4096, NBRDF_NN_INFER, &runner, err);
  if (st) return st;
  double *img = malloc((PER_BRDF + PER_GRAZING) * sizeof *img);
  double *all_ref = malloc((PER_BRDF + PER_GRAZING) * sizeof *all_ref);
  double *rho = malloc(n * NT * sizeof *rho);
  float *sigma = model ? malloc(n * sizeof *sigma) : NULL,
        *w = model ? malloc(n * sizeof *w) : NULL;
  if (!img || !all_ref || !rho || (model && (!sigma || !w)))
    st = core_fail(err, NBRDF_ERR_MEMORY, "evaluate: out of memory");
  /* Decoded albedo with the proxy lobe of each latent as one more technique. */
  if (!st && model) st = nbrdf_model_proxy_params(model, n, lat, sigma, w, err);
  if (!st)
    st = model_albedo_decoded(dec, &runner, n, lat, sigma, NT, eval_theta_all_deg,
                              DECODED_ALBEDO_SAMPLES, UINT64_C(0x616c6265646f), rho, NULL, err);
  eval_decoder_lobe g = {dec, &runner, NULL};
  for (size_t i = 0; i < n && !st; i++) {
    eval_case *c = &cases[i];
    g.latent = lat + i * D;
    /* Decoded images at all six angles, the references beside them. */
    st = lobe_images(eval_decoder_lobe_fn, &g, NBRDF_LOBE_RES, NBRDF_LOBE_N_THETA, lobe_theta_deg,
                     img, err);
    if (!st)
      st = lobe_images(eval_decoder_lobe_fn, &g, NBRDF_LOBE_RES, EVAL_N_GRAZING, grazing_deg,
                       img + PER_BRDF, err);
    if (st) break;
    memcpy(all_ref, ref + i * PER_BRDF, PER_BRDF * sizeof *all_ref);
    memcpy(all_ref + PER_BRDF, x->images + i * PER_GRAZING, PER_GRAZING * sizeof *all_ref);
    for (int t = 0; t < NT; t++)
      c->pointwise[t] =
          lobe_pointwise_error(NBRDF_LOBE_RES, all_ref + t * IMG, img + t * IMG, POINTWISE_FLOOR);
    /* Over all six images: each image's pixels against its own peak. */
    double *e = malloc(NT * IMG * sizeof *e);
    size_t m = 0;
    if (e)
      for (int t = 0; t < NT; t++) {
        double peak = 0.0, wo[3];
        for (int row = 0; row < NBRDF_LOBE_RES; row++)
          for (int col = 0; col < NBRDF_LOBE_RES; col++)
            if (lobe_pixel_wo(NBRDF_LOBE_RES, row, col, wo))
              peak = fmax(peak, all_ref[t * IMG + (size_t)row * NBRDF_LOBE_RES + col] / wo[2]);
        for (int row = 0; row < NBRDF_LOBE_RES; row++)
          for (int col = 0; col < NBRDF_LOBE_RES; col++) {
            size_t k = t * IMG + (size_t)row * NBRDF_LOBE_RES + col;
            if (lobe_pixel_wo(NBRDF_LOBE_RES, row, col, wo) && peak > 0.0 &&
                all_ref[k] / wo[2] > POINTWISE_FLOOR * peak)
              e[m++] = fabs(img[k] / all_ref[k] - 1.0);
          }
      }
    c->pointwise_all = e ? lobe_median_finite(m, e) : NAN;
    free(e);
    /* Mirror direction. */
    nbrdf_query q[NT];
    double f[NT];
    for (int t = 0; t < NT; t++) {
      double th = eval_theta_all_deg[t] * (M_PI / 180.0);
      q[t] = (nbrdf_query){{sin(th), 0.0, cos(th)}, {-sin(th), 0.0, cos(th)}};
    }
    st = eval_decoder_lobe_fn(&g, NT, q, f, err);
    for (int t = 0; t < NT && !st; t++) {
      double r = x->mirror[i * NT + t];
      c->mirror_error[t] = r > 0.0 ? fabs(f[t] / r - 1.0) : NAN;
      c->albedo[t] = rho[i * NT + t];
      c->albedo_ref[t] = x->albedo[i * NT + t];
      c->albedo_ref_se[t] = x->albedo_se[i * NT + t];
    }
  }
  free(img), free(all_ref), free(rho), free(sigma), free(w);
  model_runner_destroy(&runner);
  return st;
}

void eval_summarise_extra(eval_result *r) {
  double *v = malloc(((size_t)r->n + 1) * sizeof *v);
  if (!v) return;
  double best = -1.0;
  for (int t = 0; t < NT; t++) {
    for (int i = 0; i < r->n; i++)
      v[i] = r->cases[i].pointwise[t];
    r->median_pointwise[t] = lobe_median_finite((size_t)r->n, v);
    for (int i = 0; i < r->n; i++)
      v[i] = r->cases[i].mirror_error[t];
    r->median_mirror[t] = lobe_median_finite((size_t)r->n, v);
    r->max_decoded_albedo[t] = 0.0, r->max_albedo_excess[t] = -INFINITY;
    for (int i = 0; i < r->n; i++) {
      const eval_case *c = &r->cases[i];
      r->max_decoded_albedo[t] = fmax(r->max_decoded_albedo[t], c->albedo[t]);
      r->max_albedo_excess[t] = fmax(r->max_albedo_excess[t], c->albedo[t] - c->albedo_ref[t]);
      if (c->albedo[t] > best)
        best = c->albedo[t], r->max_decoded_albedo_index = i, r->max_decoded_albedo_theta = t;
    }
  }
  for (int i = 0; i < r->n; i++)
    v[i] = r->cases[i].pointwise_all;
  r->median_pointwise_all = lobe_median_finite((size_t)r->n, v);
  free(v);
}
