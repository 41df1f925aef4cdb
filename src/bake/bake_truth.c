#include "bake/bake_truth.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "brdf/brdf_handle.h"
#include "brdf/layered_lobe.h"
#include "core/error.h"
#include "core/rng.h"
#include "model/material.h"

const double bake_lobe_theta_deg[BAKE_LOBE_N_THETA] = {0.0, 30.0, 60.0, 80.0, 85.0, 89.0};

#define TRUTH_TAG 0x6e62747275746830ull /* fit samples' family */
#define LOBE_TAG 0x6e62747275746831ull  /* held-out lobes' family */
#define AZIMUTH_TAG 0x6e62747275746832ull /* held-out lobes' azimuths */

void bake_tuple_params(const bake_tuple *t, train_params *p) {
  memset(p, 0, sizeof *p);
  p->kind = TRAIN_LAYERED2;
  p->n_coats = 1;
  p->coat[0].alpha = t->p[NBRDF_BAKE_ALPHA1];
  p->coat[0].eta = t->p[NBRDF_BAKE_ETA];
  p->coat[0].albedo = t->p[NBRDF_BAKE_ALBEDO];
  p->coat[0].sigma_t = t->p[NBRDF_BAKE_SIGMA_T];
  p->base_alpha = t->p[NBRDF_BAKE_ALPHA2];
  p->base_r0 = t->p[NBRDF_BAKE_R0];
}

typedef struct shared_state {
  const bake_truth_settings *s;
  volatile sig_atomic_t stop; /* set by the caller's thread on cancel */
  size_t done;                /* finished tuples (atomic) */
  pthread_t caller;           /* only the caller's thread reports progress */
} shared_state;

static int hook_tick(void *user) {
  shared_state *sh = user;
  /* The walks' own OpenMP regions are nested (one thread each), where every
   * thread is number 0: compare thread identities instead. */
  if (!pthread_equal(pthread_self(), sh->caller)) return 0;
  size_t done;
#pragma omp atomic read
  done = sh->done;
  const bake_truth_settings *s = sh->s;
  if ((s->cancel && *s->cancel) ||
      (s->ticker &&
       core_ticker_tick(s->ticker, "ground truth", s->done0 + (double)done, s->total, 0)))
    sh->stop = 1;
  return sh->stop;
}

/* Runs job(k) for k < n over OpenMP threads with the cancel/progress hook;
 * the first failure (lowest k) is returned. */
typedef nbrdf_status (*truth_job)(const bake_truth_settings *s, const bake_tuple *t, size_t k,
                                  const brdf_layered_lobe_hook *hook, void *out, nbrdf_error *err);

static nbrdf_status run_jobs(const bake_tuple *t, size_t n, const bake_truth_settings *s,
                             truth_job job, void *out, nbrdf_error *err) {
  shared_state sh = {s, 0, 0, pthread_self()};
  brdf_layered_lobe_hook hook = {&sh.stop, hook_tick, &sh};
  nbrdf_status *sts = calloc(n ? n : 1, sizeof *sts);
  nbrdf_error *errs = calloc(n ? n : 1, sizeof *errs);
  if (!sts || !errs) {
    free(sts), free(errs);
    return core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for the ground truth");
  }
#pragma omp parallel for schedule(dynamic, 1)
  for (long k = 0; k < (long)n; k++) {
    if (sh.stop) {
      sts[k] = NBRDF_ERR_CANCELLED;
      continue;
    }
    sts[k] = job(s, t, (size_t)k, &hook, out, &errs[k]);
#pragma omp atomic update
    sh.done++;
    hook_tick(&sh);
  }
  nbrdf_status st = NBRDF_OK;
  if (sh.stop)
    st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled during the ground truth");
  for (size_t k = 0; k < n && st == NBRDF_OK; k++)
    if (sts[k] != NBRDF_OK) {
      if (err) *err = errs[k];
      st = sts[k];
    }
  free(sts), free(errs);
  return st;
}

static train_dataset_settings dataset_settings(const bake_truth_settings *s) {
  train_dataset_settings ds = TRAIN_DATASET_SETTINGS_DEFAULT;
  ds.incident = s->incident, ds.outgoing = s->outgoing, ds.sampled = s->sampled;
  ds.spp = s->spp, ds.threads = 1;
  return ds;
}

static nbrdf_status sample_job(const bake_truth_settings *s, const bake_tuple *t, size_t k,
                               const brdf_layered_lobe_hook *hook, void *out, nbrdf_error *err) {
  train_dataset_settings ds = dataset_settings(s);
  train_params p;
  bake_tuple_params(&t[k], &p);
  size_t row = (size_t)ds.incident * ds.outgoing * TRAIN_DATASET_FLOATS;
  return train_samples_generate_hooked(&ds, core_hash64(s->seed, TRUTH_TAG), k, &p, hook,
                                       (float *)out + k * row, err);
}

nbrdf_status bake_truth_samples(const bake_tuple *t, size_t n, const bake_truth_settings *s,
                                train_samples *out, nbrdf_error *err) {
  train_dataset_settings ds = dataset_settings(s);
  size_t per = (size_t)ds.incident * ds.outgoing;
  float *buf = malloc(sizeof(float) * per * TRAIN_DATASET_FLOATS * (n ? n : 1));
  if (!buf)
    return core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for %zu tuples' samples", n);
  nbrdf_status st = run_jobs(t, n, s, sample_job, buf, err);
  for (size_t k = 0; k < n && st == NBRDF_OK; k++) {
    train_params p;
    bake_tuple_params(&t[k], &p);
    st = train_samples_append(out, &p, per, buf + k * per * TRAIN_DATASET_FLOATS, err);
  }
  free(buf);
  return st;
}

double bake_lobe_azimuth(uint64_t seed, size_t k, int i) {
  uint64_t h = core_hash64(core_hash64(seed, AZIMUTH_TAG), k * BAKE_LOBE_N_THETA + (size_t)i);
  return 2.0 * M_PI * (double)(h >> 11) * (1.0 / 9007199254740992.0);
}

int bake_lobe_pixel_wo(int res, int row, int col, float wo[3]) {
  double x = -1.0 + (col + 0.5) * 2.0 / res, y = 1.0 - (row + 0.5) * 2.0 / res;
  double r2 = x * x + y * y;
  if (r2 >= 1.0) return 0;
  wo[0] = (float)x, wo[1] = (float)y, wo[2] = (float)sqrt(1.0 - r2);
  return 1;
}

static nbrdf_status lobe_job(const bake_truth_settings *s, const bake_tuple *t, size_t k,
                             const brdf_layered_lobe_hook *hook, void *out, nbrdf_error *err) {
  /* The tuple is prepared (model_material_prepare): inside the trained range already, so
   * the ground truth is that of the values the texel's latent stands for. */
  double p[MODEL_MATERIAL_PARAMS];
  for (int i = 0; i < MODEL_MATERIAL_PARAMS; i++)
    p[i] = t[k].p[i];
  nbrdf_brdf *b = NULL;
  nbrdf_status st = model_material_truth(p, &b, err);
  if (st != NBRDF_OK) return st;
  size_t px = (size_t)s->lobe_res * s->lobe_res;
  double *images = (double *)out + k * BAKE_LOBE_N_THETA * px;
  for (int i = 0; i < BAKE_LOBE_N_THETA && st == NBRDF_OK; i++) {
    uint64_t seed = core_hash64(core_hash64(s->seed, LOBE_TAG), k * BAKE_LOBE_N_THETA + i);
    int ok = brdf_layered_lobe_image_hooked(&brdf_handle_bsdf(b)->layered,
                                            bake_lobe_theta_deg[i] * (M_PI / 180.0), s->lobe_res,
                                            s->lobe_walks, seed, 1, hook, images + i * px, NULL);
    if (ok < 0)
      st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled during the ground truth");
    else if (!ok)
      st = core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory in the lobe estimator");
  }
  nbrdf_brdf_destroy(b);
  return st;
}

nbrdf_status bake_truth_lobes(const bake_tuple *t, size_t n, const bake_truth_settings *s,
                              double *images, nbrdf_error *err) {
  return run_jobs(t, n, s, lobe_job, images, err);
}
