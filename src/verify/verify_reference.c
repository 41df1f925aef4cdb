/* Ground-truth lobe images for verify, one entry per distinct parameter
 * tuple: texels painted with the same values (a constant input, a few
 * painted regions) share one reference, which is what keeps verify cheap on
 * real maps. Each reference is two independent runs of the whole-lobe
 * estimator (src/brdf/layered_lobe.h): their mean is compared with the
 * texture, their difference is the reference's own noise (docs/METRICS.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brdf/brdf_handle.h"
#include "brdf/layered_lobe.h"
#include "core/error.h"
#include "core/rng.h"
#include "model/material.h"
#include "verify/verify_internal.h"

typedef struct ref_entry {
  verify_tuple key;
  double *images; /* run a, then run b: 2 × VERIFY_SET */
} ref_entry;

struct verify_refs {
  int walks, threads;
  uint64_t seed;
  const volatile sig_atomic_t *stop;
  int (*tick)(void *user, int image);
  void *tick_user;
  ref_entry *e;
  size_t n, cap;
};

verify_refs *verify_refs_create(int walks, uint64_t seed, int threads) {
  verify_refs *r = calloc(1, sizeof *r);
  if (r) r->walks = walks, r->seed = seed, r->threads = threads;
  return r;
}

void verify_refs_free(verify_refs *r) {
  if (!r) return;
  for (size_t i = 0; i < r->n; i++)
    free(r->e[i].images);
  free(r->e);
  free(r);
}

size_t verify_refs_count(const verify_refs *r) { return r->n; }

void verify_refs_set_cancel(verify_refs *r, const volatile sig_atomic_t *stop,
                            int (*tick)(void *user, int image), void *user) {
  r->stop = stop, r->tick = tick, r->tick_user = user;
}

/* The seed of a tuple depends on its values only, so a texel's reference is
 * the same whichever texels were verified with it. */
static uint64_t tuple_seed(uint64_t seed, const verify_tuple *t) {
  uint64_t h = seed;
  for (int i = 0; i < NBRDF_BAKE_PARAM_COUNT; i++) {
    uint32_t bits;
    memcpy(&bits, &t->p[i], sizeof bits);
    h = core_hash64(h, bits);
  }
  return h;
}

/* The hook's tick: the lobe image being computed joins the caller's tick. */
typedef struct image_tick {
  const verify_refs *r;
  int image;
} image_tick;

static int on_tick(void *user) {
  const image_tick *t = user;
  return t->r->tick(t->r->tick_user, t->image);
}

static nbrdf_status estimate(const verify_refs *r, const verify_tuple *t, double *images,
                             nbrdf_error *err) {
  double p[MODEL_MATERIAL_PARAMS];
  for (int i = 0; i < MODEL_MATERIAL_PARAMS; i++)
    p[i] = t->p[i];
  nbrdf_brdf *layered = NULL;
  nbrdf_status st = model_material_truth(p, &layered, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "verify: ground truth: ");
    return st;
  }
  const brdf_bsdf_layered *l = &brdf_handle_bsdf(layered)->layered;
  const uint64_t base = tuple_seed(r->seed, t);
  const size_t per = (size_t)NBRDF_LOBE_RES * NBRDF_LOBE_RES;
  for (int run = 0; run < 2 && st == NBRDF_OK; run++)
    for (int k = 0; k < VERIFY_N_THETA && st == NBRDF_OK; k++) {
      double *img = images + (size_t)run * VERIFY_SET + (size_t)k * per;
      image_tick it = {r, run * VERIFY_N_THETA + k};
      brdf_layered_lobe_hook hook = {r->stop, r->tick ? on_tick : NULL, &it};
      int ok = brdf_layered_lobe_image_hooked(l, verify_theta_deg[k] * (M_PI / 180.0), NBRDF_LOBE_RES,
                                              r->walks, core_hash64(base, (uint64_t)(run * 16 + k)),
                                              r->threads, &hook, img, NULL);
      if (ok < 0)
        st = core_fail(err, NBRDF_ERR_CANCELLED, "verify: cancelled in a ground truth");
      else if (!ok)
        st = core_fail(err, NBRDF_ERR_MEMORY, "verify: out of memory in the ground truth");
    }
  nbrdf_brdf_destroy(layered);
  return st;
}

nbrdf_status verify_refs_get(verify_refs *r, const verify_tuple *t, const double **a,
                             const double **b, size_t *clamped, nbrdf_error *err) {
  verify_tuple k = *t;
  /* The values as painted, clamped only where the ground truth cannot represent them. */
  *clamped += model_material_clamp(MODEL_RANGE_TRUTH, NULL, NULL, k.p);
  /* A linear search: every new entry costs seconds of random walks, so
   * there are never enough of them for the search to matter. */
  for (size_t i = 0; i < r->n; i++)
    if (!memcmp(&r->e[i].key, &k, sizeof k)) {
      *a = r->e[i].images, *b = r->e[i].images + VERIFY_SET;
      return NBRDF_OK;
    }
  if (r->n == r->cap) {
    size_t cap = r->cap ? 2 * r->cap : 16;
    ref_entry *e = realloc(r->e, cap * sizeof *e);
    if (!e) return core_fail(err, NBRDF_ERR_MEMORY, "verify: out of memory for references");
    r->e = e, r->cap = cap;
  }
  double *images = malloc(2 * VERIFY_SET * sizeof *images);
  if (!images) return core_fail(err, NBRDF_ERR_MEMORY, "verify: out of memory for a reference");
  nbrdf_status st = estimate(r, &k, images, err);
  if (st != NBRDF_OK) {
    free(images);
    return st;
  }
  r->e[r->n++] = (ref_entry){k, images};
  *a = images, *b = images + VERIFY_SET;
  return NBRDF_OK;
}
