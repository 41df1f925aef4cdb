/* Generation of a data set (train/dataset.h), in batches of BRDFs computed in
 * parallel and appended in order, so that the file is the same for any thread
 * count and an interrupted run leaves a valid prefix to resume from. */
#include "train/dataset.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "brdf/brdf_handle.h"
#include "brdf/layered_lobe.h"
#include "core/error.h"
#include "core/rng.h"
#include "core/warp.h"
#include "nn/safetensors.h"
#include "train/dataset_format.h"

/* Domain tags of the per-BRDF random streams (directions, sampling, walks). */
#define DIR_TAG UINT64_C(0x6e62726464697273)
#define WALK_TAG UINT64_C(0x6e62726477616c6b)
#define THETA_I_MAX_DEG 89.0

nbrdf_status train_dataset_check_settings(const train_dataset_settings *s, nbrdf_error *err) {
  if ((unsigned)s->kind > TRAIN_SINGLE)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "dataset: unknown kind %d", (int)s->kind);
  if (s->incident < 1 || s->incident > 4096)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "dataset: incident = %d must be in [1, 4096]",
                     s->incident);
  if (s->outgoing < 1 || s->outgoing > 65536)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "dataset: outgoing = %d must be in [1, 65536]",
                     s->outgoing);
  if (s->sampled < 0 || s->sampled > s->outgoing)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "dataset: sampled = %d must be in [0, %d]",
                     s->sampled, s->outgoing);
  if (s->spp < 2 || s->spp > (1 << 30))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "dataset: spp = %d must be >= 2 (standard errors need two walks)", s->spp);
  if (s->threads < 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "dataset: threads = %d must be >= 0", s->threads);
  return NBRDF_OK;
}

static void store(float *x, vec3 wi, vec3 wo) {
  x[0] = (float)wi.x, x[1] = (float)wi.y, x[2] = (float)wi.z;
  x[3] = (float)wo.x, x[4] = (float)wo.y, x[5] = (float)wo.z;
}

/* The M outgoing directions for wi (see dataset.h). */
static nbrdf_status choose_outgoing(const train_dataset_settings *s, const nbrdf_brdf *b, vec3 wi,
                                    uint64_t seed, core_rng *rng, vec3 *wo, nbrdf_error *err) {
  int uniform = s->outgoing - s->sampled;
  for (int j = 0; j < s->outgoing; j++) {
    double u1 = core_rng_uniform(rng), u2 = core_rng_uniform(rng);
    vec3 w =
        (j % 2 == 0) ? core_warp_uniform_hemisphere(u1, u2) : core_warp_cosine_hemisphere(u1, u2);
    if (j >= uniform) {
      double wi3[3] = {wi.x, wi.y, wi.z}, o[3], weight;
      nbrdf_status st = nbrdf_brdf_sample(b, wi3, seed, (uint64_t)j, o, &weight, err);
      if (st) return st;
      if (weight > 0.0 && o[2] > 1e-4)
        w = v3(o[0], o[1], o[2]);
      else
        w = core_warp_cosine_hemisphere(u1, u2);
    }
    /* Keep clear of the horizon, where a direction would be rejected. */
    if (!(w.z > 1e-6)) w = v3_normalize(v3(w.x, w.y, 1e-6));
    wo[j] = v3_normalize(w);
  }
  return NBRDF_OK;
}

static nbrdf_status samples_generate(const train_dataset_settings *s, uint64_t family,
                                     uint64_t index, const train_params *params,
                                     const brdf_layered_lobe_hook *hook, float *samples,
                                     nbrdf_error *err);

nbrdf_status train_dataset_generate_one(const train_dataset_settings *s, uint64_t index,
                                        const brdf_layered_lobe_hook *hook, train_params *params,
                                        float *samples, nbrdf_error *err) {
  nbrdf_status st = train_dataset_check_settings(s, err);
  if (st) return st;
  uint64_t family = train_family_seed(s->seed);
  train_params_draw_from(family, s->kind, s->draws, index, params);
  return samples_generate(s, family, index, params, hook, samples, err);
}

nbrdf_status train_samples_generate(const train_dataset_settings *s, uint64_t family,
                                    uint64_t index, const train_params *params, float *samples,
                                    nbrdf_error *err) {
  return samples_generate(s, family, index, params, NULL, samples, err);
}

nbrdf_status train_samples_generate_hooked(const train_dataset_settings *s, uint64_t family,
                                           uint64_t index, const train_params *params,
                                           const brdf_layered_lobe_hook *hook, float *samples,
                                           nbrdf_error *err) {
  return samples_generate(s, family, index, params, hook, samples, err);
}

static nbrdf_status samples_generate(const train_dataset_settings *s, uint64_t family,
                                     uint64_t index, const train_params *params,
                                     const brdf_layered_lobe_hook *hook, float *samples,
                                     nbrdf_error *err) {
  nbrdf_brdf *b = NULL;
  nbrdf_status st = train_params_create(params, &b, err);
  if (st) return st;
  size_t m = (size_t)s->outgoing;
  vec3 *wo = malloc(m * sizeof *wo);
  nbrdf_query *q = malloc(m * sizeof *q);
  double *f = malloc(2 * m * sizeof *f), *se = f ? f + m : NULL;
  if (!wo || !q || !f) {
    st = core_fail(err, NBRDF_ERR_MEMORY, "dataset: out of memory for %zu directions", m);
    goto done;
  }
  core_rng rng;
  core_rng_init(&rng, core_hash64(family, DIR_TAG), index);
  for (int i = 0; i < s->incident && !st; i++) {
    /* One jittered θi per stratum of [0°, 89°). */
    double theta = (i + core_rng_uniform(&rng)) / s->incident * THETA_I_MAX_DEG * M_PI / 180.0;
    vec3 wi = v3(sin(theta), 0.0, cos(theta));
    uint64_t stream = index * (uint64_t)s->incident + (uint64_t)i;
    uint64_t seed = core_hash64(core_hash64(family, WALK_TAG), stream);
    st = choose_outgoing(s, b, wi, seed, &rng, wo, err);
    if (st) break;
    if (nbrdf_brdf_is_stochastic(b)) {
      int ok = brdf_layered_lobe_eval_hooked(&brdf_handle_bsdf(b)->layered, wi, m, wo, s->spp, seed,
                                             1, hook, f, se);
      if (ok < 0)
        st = core_fail(err, NBRDF_ERR_CANCELLED, "dataset: BRDF %llu stopped",
                       (unsigned long long)index);
      else if (!ok)
        st = core_fail(err, NBRDF_ERR_MEMORY, "dataset: out of memory in the lobe estimator");
    } else {
      for (size_t j = 0; j < m; j++) {
        q[j] = (nbrdf_query){{wi.x, wi.y, wi.z}, {wo[j].x, wo[j].y, wo[j].z}};
        se[j] = 0.0;
      }
      nbrdf_eval_options o = {seed, 1, 1};
      st = nbrdf_brdf_eval(b, m, q, &o, f, NULL, err);
    }
    for (size_t j = 0; j < m && !st; j++) {
      float *x = samples + ((size_t)i * m + j) * TRAIN_DATASET_FLOATS;
      store(x, wi, wo[j]);
      x[6] = (float)f[j];
      x[7] = (float)se[j];
      if (!isfinite(x[6]) || !isfinite(x[7]))
        st = core_fail(err, NBRDF_ERR_INTERNAL,
                       "dataset: BRDF %llu, sample %zu: value %g ± %g does not fit a float",
                       (unsigned long long)index, (size_t)i * m + j, f[j], se[j]);
    }
  }
done:
  free(wo), free(q), free(f);
  nbrdf_brdf_destroy(b);
  return st;
}
