/* Public evaluation: batched queries (OpenMP, one random stream per query so
 * that results do not depend on the thread count), sampling for renderers,
 * directional albedo. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

#include "brdf/brdf_handle.h"
#include "brdf/dielectric.h"
#include "brdf/layered.h"
#include "core/error.h"

/* Mean and standard error of the mean of one query's spp walks (Welford). */
static void eval_stochastic(const brdf_bsdf_layered *l, vec3 wo, vec3 wi, uint64_t seed,
                            uint64_t stream, int spp, double *f, double *se) {
  core_rng rng;
  core_rng_init(&rng, seed, stream);
  double mean = 0.0, m2 = 0.0;
  for (int s = 0; s < spp; s++) {
    double x = brdf_bsdf_layered_walk(l, wo, wi, BSDF_RADIANCE, &rng);
    double d = x - mean;
    mean += d / (s + 1);
    m2 += d * (x - mean);
  }
  /* The top's own reflection is exact: it adds to the mean, not to the error. */
  *f = brdf_bsdf_dielectric_eval(&l->top, wo, wi, BSDF_RADIANCE) + mean;
  *se = spp > 1 ? sqrt(m2 / ((double)(spp - 1) * spp)) : INFINITY;
}

static int thread_count(int requested) { return requested > 0 ? requested : omp_get_max_threads(); }

nbrdf_status nbrdf_brdf_eval_many(size_t n, const nbrdf_brdf *const *brdfs,
                                  const nbrdf_query *queries, const nbrdf_eval_options *options,
                                  double *f, double *f_stderr, nbrdf_error *err) {
  nbrdf_eval_options opts = NBRDF_EVAL_OPTIONS_DEFAULT;
  if (options) opts = *options;
  if (n == 0) return NBRDF_OK;
  if (!brdfs || !queries || !f)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "eval: brdfs, queries and f must not be NULL");
  if (opts.spp < 1)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "eval: spp = %d must be >= 1", opts.spp);
  if (opts.threads < 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "eval: threads = %d must be >= 0 (0 = all)",
                     opts.threads);
  for (size_t k = 0; k < n; k++) {
    char what[64];
    vec3 v;
    if (!brdfs[k]) return core_fail(err, NBRDF_ERR_ARGUMENT, "query %zu: BRDF is NULL", k);
    snprintf(what, sizeof what, "query %zu: wi", k);
    nbrdf_status st = brdf_check_direction(queries[k].wi, what, &v, err);
    if (st) return st;
    snprintf(what, sizeof what, "query %zu: wo", k);
    if ((st = brdf_check_direction(queries[k].wo, what, &v, err))) return st;
  }

  long long bad = -1; /* smallest query index with a non-finite result */
  long long count = (long long)n;
  /* Walks make queries costly and uneven; analytic ones are cheap: hand
   * them out in blocks. (Scheduling never changes the results.) */
  int block = 256;
  for (size_t k = 0; k < n && block > 1; k++)
    if (brdf_bsdf_is_stochastic(&brdfs[k]->b)) block = 1;
#pragma omp parallel for num_threads(thread_count(opts.threads)) schedule(dynamic, block)
  for (long long k = 0; k < count; k++) {
    const brdf_bsdf *b = &brdfs[k]->b;
    vec3 wi, wo;
    brdf_check_direction(queries[k].wi, "", &wi, NULL);
    brdf_check_direction(queries[k].wo, "", &wo, NULL);
    double value, se = 0.0;
    /* pbrt's order: the walk starts from wo (the sensor side) and ends by
     * next-event estimation towards wi; the BRDF is reciprocal either way. */
    if (b->kind == BSDF_LAYERED)
      eval_stochastic(&b->layered, wo, wi, opts.seed, (uint64_t)k, opts.spp, &value, &se);
    else
      value = brdf_bsdf_eval(b, wo, wi, BSDF_RADIANCE, NULL);
    f[k] = value;
    if (f_stderr) f_stderr[k] = se;
    if (!isfinite(value) || isnan(se)) {
#pragma omp critical(brdf_eval_bad)
      if (bad < 0 || k < bad) bad = k;
    }
  }
  if (bad >= 0)
    return core_fail(err, NBRDF_ERR_INTERNAL,
                     "query %lld: the estimate is not finite (a bug in nbrdf: please report "
                     "it with the BRDF's parameters and directions)",
                     bad);
  return NBRDF_OK;
}

nbrdf_status nbrdf_brdf_eval(const nbrdf_brdf *brdf, size_t n, const nbrdf_query *queries,
                             const nbrdf_eval_options *options, double *f, double *f_stderr,
                             nbrdf_error *err) {
  if (n == 0) return NBRDF_OK;
  if (!brdf) return core_fail(err, NBRDF_ERR_ARGUMENT, "eval: BRDF is NULL");
  const nbrdf_brdf **many = malloc(n * sizeof *many);
  if (!many) return core_fail(err, NBRDF_ERR_MEMORY, "eval: out of memory for %zu queries", n);
  for (size_t k = 0; k < n; k++)
    many[k] = brdf;
  nbrdf_status st = nbrdf_brdf_eval_many(n, many, queries, options, f, f_stderr, err);
  free(many);
  return st;
}

/* One draw of the public sampler: ωo for ωi from stream (seed, index). */
static double sample_one(const brdf_bsdf *b, vec3 wi, uint64_t seed, uint64_t index, vec3 *wo) {
  core_rng rng;
  core_rng_init(&rng, seed, index);
  brdf_bsdf_sample s;
  /* A dielectric as a BRDF is its reflection lobe: sample that lobe only. */
  if (brdf_bsdf_sample_dir(b, wi, BSDF_RADIANCE, BSDF_REFLECTION, &rng, &s) && s.wi.z > 0.0) {
    *wo = s.wi;
    return s.weight;
  }
  *wo = v3(0.0, 0.0, 1.0);
  return 0.0;
}

nbrdf_status nbrdf_brdf_sample(const nbrdf_brdf *brdf, const double wi[3], uint64_t seed,
                               uint64_t index, double wo[3], double *weight, nbrdf_error *err) {
  if (!brdf || !wi || !wo || !weight)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "sample: brdf, wi, wo and weight must not be NULL");
  vec3 w, out;
  nbrdf_status st = brdf_check_direction(wi, "sample: wi", &w, err);
  if (st) return st;
  double x = sample_one(&brdf->b, w, seed, index, &out);
  if (!isfinite(x) || !v3_is_finite(out))
    return core_fail(err, NBRDF_ERR_INTERNAL, "sample: non-finite weight (a bug in nbrdf)");
  wo[0] = out.x;
  wo[1] = out.y;
  wo[2] = out.z;
  *weight = x;
  return NBRDF_OK;
}

/* Samples are summed in fixed blocks, in order, so the result does not
 * depend on the thread count. */
#define ALBEDO_BLOCK 1024

nbrdf_status nbrdf_brdf_albedo(const nbrdf_brdf *brdf, double theta_i, int samples, uint64_t seed,
                               double *rho, double *rho_stderr, nbrdf_error *err) {
  if (!brdf || !rho)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "albedo: brdf and rho must not be NULL");
  if (!isfinite(theta_i) || !(theta_i >= 0.0 && theta_i < 0.5 * M_PI))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "albedo: theta_i = %g is outside [0, pi/2) radians",
                     theta_i);
  if (samples < 1)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "albedo: samples = %d must be >= 1", samples);
  vec3 wi = v3(sin(theta_i), 0.0, cos(theta_i));
  int blocks = (samples + ALBEDO_BLOCK - 1) / ALBEDO_BLOCK;
  double *sums = malloc(2 * (size_t)blocks * sizeof *sums);
  if (!sums) return core_fail(err, NBRDF_ERR_MEMORY, "albedo: out of memory");
#pragma omp parallel for schedule(dynamic, 1)
  for (int k = 0; k < blocks; k++) {
    double s1 = 0.0, s2 = 0.0;
    int end = (k + 1) * ALBEDO_BLOCK < samples ? (k + 1) * ALBEDO_BLOCK : samples;
    for (int i = k * ALBEDO_BLOCK; i < end; i++) {
      vec3 wo;
      double x = sample_one(&brdf->b, wi, seed, (uint64_t)i, &wo);
      s1 += x;
      s2 += x * x;
    }
    sums[2 * k] = s1;
    sums[2 * k + 1] = s2;
  }
  double s1 = 0.0, s2 = 0.0;
  for (int k = 0; k < blocks; k++) {
    s1 += sums[2 * k];
    s2 += sums[2 * k + 1];
  }
  free(sums);
  double mean = s1 / samples;
  double var = samples > 1 ? fmax(0.0, (s2 - s1 * mean) / (samples - 1)) : INFINITY;
  if (!isfinite(mean))
    return core_fail(err, NBRDF_ERR_INTERNAL, "albedo: non-finite estimate (a bug in nbrdf)");
  *rho = mean;
  if (rho_stderr) *rho_stderr = sqrt(var / samples);
  return NBRDF_OK;
}
