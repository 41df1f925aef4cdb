/* Ground-truth lobe images of the held-out sets, cached on disk. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "brdf/brdf_handle.h"
#include "brdf/layered_lobe.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/rng.h"
#include "core/sort.h"
#include "eval/evaluate.h"
#include "lobe/lobe.h"
#include "nn/safetensors.h"

#define IMG ((size_t)NBRDF_LOBE_RES * NBRDF_LOBE_RES)
#define PER_BRDF (NBRDF_LOBE_N_THETA * IMG)
#define REF_TAG UINT64_C(0x6e62726472656673)

static const char *const names[EVAL_SET_COUNT] = {"rep",   "single", "layer",     "layer3",
                                                  "table", "tails",  "tails-rep", "extremes"};
static const train_heldout heldout[EVAL_SET_COUNT] = {
    TRAIN_HELDOUT_REP,    TRAIN_HELDOUT_SINGLE, TRAIN_HELDOUT_LAYER, TRAIN_HELDOUT_LAYER3,
    TRAIN_HELDOUT_SINGLE, TRAIN_HELDOUT_TAILS,  TRAIN_HELDOUT_TAILS,
    TRAIN_HELDOUT_LAYER /* extremes: fixed cases; the family seeds their references only */};

int eval_set_size_max(eval_set set) { return set == EVAL_EXTREMES ? EVAL_EXTREMES_COUNT : 0; }

int eval_set_has_regions(eval_set set) { return set == EVAL_TAILS || set == EVAL_TAILS_REP; }

eval_set eval_set_reference_of(eval_set set) {
  return set == EVAL_TABLE ? EVAL_SINGLE : set == EVAL_TAILS_REP ? EVAL_TAILS : set;
}

train_heldout eval_set_heldout(eval_set set) { return heldout[set]; }

void eval_set_draw(eval_set set, uint64_t index, train_params *p) {
  if (set == EVAL_EXTREMES) {
    eval_extremes_params((int)index, p);
    return;
  }
  train_heldout h = heldout[set];
  train_params_draw_from(train_heldout_seed(h), train_heldout_kind(h),
                         eval_set_has_regions(set) ? TRAIN_DRAWS_TAILS : TRAIN_DRAWS_TABLE2, index,
                         p);
}

const char *eval_set_name(eval_set set) {
  return (unsigned)set < EVAL_SET_COUNT ? names[set] : "?";
}

int eval_set_parse(const char *name, eval_set *set) {
  for (int k = 0; k < EVAL_SET_COUNT; k++)
    if (!strcmp(name, names[k])) {
      *set = (eval_set)k;
      return 1;
    }
  return 0;
}

/* Progress inside one BRDF's reference (its layered images take seconds):
 * the ticker is asked between chunks of walks. */
typedef struct ref_tick {
  core_ticker *ticker;
  const char *stage;
  double done, total;
} ref_tick;

static int ref_tick_fn(void *user) {
  ref_tick *t = user;
  return core_ticker_tick(t->ticker, t->stage, t->done, t->total, 0);
}

nbrdf_status eval_images_of(const train_params *p, uint64_t seed, int walks,
                            const brdf_layered_lobe_hook *hook, int n_theta,
                            const double *theta_deg, double *out, nbrdf_error *err) {
  nbrdf_brdf *b = NULL;
  nbrdf_status st = train_params_create(p, &b, err);
  if (st) return st;
  if (nbrdf_brdf_is_stochastic(b)) {
    for (int t = 0; t < n_theta && !st; t++) {
      int ok = brdf_layered_lobe_image_hooked(
          &brdf_handle_bsdf(b)->layered, theta_deg[t] * (M_PI / 180.0), NBRDF_LOBE_RES, walks,
          core_hash64(seed, (uint64_t)t), 0, hook, out + t * IMG, NULL);
      if (ok < 0)
        st = core_fail(err, NBRDF_ERR_CANCELLED, "evaluate: cancelled");
      else if (!ok)
        st = core_fail(err, NBRDF_ERR_MEMORY, "evaluate: out of memory in the lobe estimator");
    }
  } else {
    lobe_brdf lb = {b, {seed, 1, 1}};
    st = lobe_images(lobe_brdf_fn, &lb, NBRDF_LOBE_RES, n_theta, theta_deg, out, err);
  }
  nbrdf_brdf_destroy(b);
  return st;
}

static void cache_path(char *out, size_t size, eval_set set, const eval_settings *s) {
  snprintf(out, size, "%s/ref-%s-n%d-w%d.safetensors", s->cache_dir, names[set], s->count,
           s->walks);
}

static int load_cache(const char *path, const eval_settings *s, double *images, double *noise) {
  nn_st_reader *r = NULL;
  if (nn_st_open(path, &r, NULL) != NBRDF_OK) return 0;
  int64_t shape[4] = {s->count, NBRDF_LOBE_N_THETA, NBRDF_LOBE_RES, NBRDF_LOBE_RES}, one = 1;
  const float *x = NULL, *nz = NULL;
  int ok = nn_st_expect(r, "images", 4, shape, &x, NULL) == NBRDF_OK &&
           nn_st_expect(r, "noise", 1, &one, &nz, NULL) == NBRDF_OK;
  if (ok) {
    for (size_t k = 0; k < (size_t)s->count * PER_BRDF; k++)
      images[k] = x[k];
    *noise = nz[0];
  }
  nn_st_close(r);
  return ok;
}

static void save_cache(const char *path, const eval_settings *s, const double *images,
                       double noise) {
  size_t n = (size_t)s->count * PER_BRDF;
  float *x = malloc(n * sizeof *x), nz = (float)noise;
  nn_st_writer *w = NULL;
  if (x && nn_st_writer_create(&w, NULL) == NBRDF_OK) {
    for (size_t k = 0; k < n; k++)
      x[k] = (float)images[k];
    int64_t shape[4] = {s->count, NBRDF_LOBE_N_THETA, NBRDF_LOBE_RES, NBRDF_LOBE_RES}, one = 1;
    mkdir(s->cache_dir, 0777);
    /* A cache that cannot be written only costs the next run time. */
    if (nn_st_writer_add_borrowed(w, "images", 4, shape, x, NULL) == NBRDF_OK &&
        nn_st_writer_add(w, "noise", 1, &one, &nz, NULL) == NBRDF_OK)
      (void)nn_st_writer_save(w, path, NULL, NULL);
  }
  nn_st_writer_destroy(w);
  free(x);
}

nbrdf_status eval_reference(eval_set set, const eval_settings *s, double *images, double *noise,
                            nbrdf_error *err) {
  char path[4096];
  set = eval_set_reference_of(set); /* the same BRDFs share one reference */
  if (s->cache_dir) {
    cache_path(path, sizeof path, set, s);
    if (load_cache(path, s, images, noise)) return NBRDF_OK;
  }
  uint64_t family = train_heldout_seed(heldout[set]);
  char stage[64];
  snprintf(stage, sizeof stage, "%s: reference", names[set]);
  int nn = s->noise_brdfs < s->count ? s->noise_brdfs : s->count, n_noise = 0;
  double *second = malloc(PER_BRDF * sizeof *second), *errs = malloc((size_t)(nn + 1) * 8);
  nbrdf_status st = second && errs ? NBRDF_OK : core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
  core_ticker ticker;
  core_ticker_init(&ticker, s->progress, s->user, NULL);
  ref_tick rt = {&ticker, stage, 0.0, s->count};
  brdf_layered_lobe_hook hook = {NULL, ref_tick_fn, &rt};
  for (int i = 0; i < s->count && !st; i++) {
    train_params p;
    eval_set_draw(set, (uint64_t)i, &p);
    uint64_t seed = core_hash64(core_hash64(family, REF_TAG), (uint64_t)i);
    rt.done = i;
    st = eval_images_of(&p, seed, s->walks, &hook, NBRDF_LOBE_N_THETA, lobe_theta_deg,
                        images + (size_t)i * PER_BRDF, err);
    if (!st && i < nn && p.n_coats > 0) {
      st = eval_images_of(&p, seed ^ UINT64_C(0x9e3779b97f4a7c15), s->walks, &hook,
                          NBRDF_LOBE_N_THETA, lobe_theta_deg, second, err);
      if (!st) errs[n_noise++] = lobe_l1_error(PER_BRDF, images + (size_t)i * PER_BRDF, second);
    }
    if (!st && core_ticker_tick(&ticker, stage, i + 1, s->count, 1))
      st = core_fail(err, NBRDF_ERR_CANCELLED, "evaluate: cancelled");
  }
  *noise = 0.0;
  if (n_noise > 0) {
    core_sort_doubles(errs, (size_t)n_noise);
    *noise = errs[n_noise / 2];
  }
  free(second), free(errs);
  if (!st && s->cache_dir) save_cache(path, s, images, *noise);
  return st;
}
