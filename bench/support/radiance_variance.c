/* Reflected-radiance estimators and their measured variance (radiance_variance.h). */
#include "support/radiance_variance.h"

#include <math.h>
#include <stdlib.h>

#include "brdf/ggx.h"
#include "core/error.h"
#include "core/rng.h"
#include "core/warp.h"
#include "model/proxy.h"

static const char *const names[BENCH_IS_COUNT] = {"proxy", "cosine", "ggx", "proxy+cosine MIS"};

const char *bench_is_strategy_name(bench_is_strategy s) {
  return (unsigned)s < BENCH_IS_COUNT ? names[s] : "?";
}

static double cosine_pdf(vec3 wi) { return wi.z > 0.0 ? wi.z / M_PI : 0.0; }

/* Reflection about the microfacet normal: dωi = 4 |ωo·m| dωm (Walter et al. 2007). */
static double ggx_pdf(double alpha, vec3 wo, vec3 wi) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return 0.0;
  vec3 m = v3_normalize(v3_add(wo, wi));
  double om = v3_dot(wo, m);
  return om > 0.0 ? brdf_ggx_vndf_pdf(alpha, wo, m) / (4.0 * om) : 0.0;
}

double bench_is_pdf(bench_is_strategy s, const bench_is_lobe *l, vec3 wo, vec3 wi) {
  switch (s) {
  case BENCH_IS_PROXY:
    return model_proxy_pdf(l->sigma, l->w, wo, wi);
  case BENCH_IS_COSINE:
    return cosine_pdf(wi);
  case BENCH_IS_GGX:
    return ggx_pdf(l->alpha1, wo, wi);
  case BENCH_IS_MIX:
    return 0.5 * (model_proxy_pdf(l->sigma, l->w, wo, wi) + cosine_pdf(wi));
  default:
    return 0.0;
  }
}

double bench_is_sample(bench_is_strategy s, const bench_is_lobe *l, vec3 wo, const double u[3],
                       vec3 *wi) {
  vec3 d;
  double pdf = 0.0;
  switch (s) {
  case BENCH_IS_PROXY:
    if (!model_proxy_sample(l->sigma, l->w, wo, u[0], u[1], u[2], &d, &pdf)) return 0.0;
    break;
  case BENCH_IS_COSINE:
    d = core_warp_cosine_hemisphere(u[1], u[2]);
    pdf = cosine_pdf(d);
    break;
  case BENCH_IS_GGX: {
    vec3 m;
    if (!brdf_ggx_sample_vndf(l->alpha1, wo, u[1], u[2], &m)) return 0.0;
    d = v3_sub(v3_scale(m, 2.0 * v3_dot(wo, m)), wo);
    pdf = ggx_pdf(l->alpha1, wo, d);
    break;
  }
  case BENCH_IS_MIX: {
    /* u[0] picks the strategy and is reused, rescaled, by the proxy's own lobe choice. */
    if (u[0] < 0.5) {
      double v[3] = {2.0 * u[0], u[1], u[2]};
      if (bench_is_sample(BENCH_IS_PROXY, l, wo, v, &d) <= 0.0) return 0.0;
    } else {
      d = core_warp_cosine_hemisphere(u[1], u[2]);
    }
    pdf = bench_is_pdf(BENCH_IS_MIX, l, wo, d);
    break;
  }
  default:
    return 0.0;
  }
  if (!(d.z > 0.0) || !(pdf > 0.0) || !isfinite(pdf)) return 0.0;
  *wi = d;
  return pdf;
}

/* Sample variance of `reps` estimates, each the mean of the first n values of
 * its block of `stride`. */
static double rep_variance(const double *c, int reps, int stride, int n) {
  double sum = 0.0, sum2 = 0.0;
  for (int r = 0; r < reps; r++) {
    double m = 0.0;
    for (int k = 0; k < n; k++)
      m += c[(size_t)r * stride + k];
    m /= n;
    sum += m, sum2 += m * m;
  }
  double mean = sum / reps;
  return fmax(0.0, (sum2 - reps * mean * mean) / (reps - 1));
}

nbrdf_status bench_is_variance(const bench_is_setup *su, const bench_is_lobe *lobe, vec3 wo,
                               uint64_t stream, bench_is_result *out, nbrdf_error *err) {
  int nmax = 0;
  for (int k = 0; k < su->n_counts; k++)
    nmax = su->counts[k] > nmax ? su->counts[k] : nmax;
  if (su->reps < 2 || su->n_counts < 1 || su->n_counts > BENCH_IS_MAX_N || nmax < 1 ||
      !(wo.z > 0.0))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "radiance variance: need reps >= 2, 1..%d sample counts >= 1 and wo above "
                     "the horizon",
                     BENCH_IS_MAX_N);
  size_t total = (size_t)su->reps * (size_t)nmax;
  double *c = malloc(total * sizeof *c), *f = malloc(total * sizeof *f);
  double *weight = malloc(total * sizeof *weight);
  size_t *slot = malloc(total * sizeof *slot);
  nbrdf_query *q = malloc(total * sizeof *q);
  nbrdf_status st = c && f && weight && slot && q
                        ? NBRDF_OK
                        : core_fail(err, NBRDF_ERR_MEMORY, "radiance variance: out of memory");
  /* Pooled radiance: inverse-variance weighted; a zero-variance estimator is exact. */
  double wsum = 0.0, wmean = 0.0, exact = -1.0;
  for (int s = 0; s < BENCH_IS_COUNT && !st; s++) {
    core_rng rng;
    core_rng_init(&rng, su->seed, core_hash64(stream, (uint64_t)s));
    size_t n = 0, lost = 0;
    for (size_t k = 0; k < total; k++) {
      double u[3] = {core_rng_uniform(&rng), core_rng_uniform(&rng), core_rng_uniform(&rng)};
      vec3 wi;
      double pdf = bench_is_sample((bench_is_strategy)s, lobe, wo, u, &wi);
      c[k] = 0.0;
      if (pdf <= 0.0) {
        lost++;
        continue;
      }
      double li = su->radiance(su->radiance_user, wi);
      if (!(li > 0.0)) continue; /* no light: no BRDF query needed */
      q[n] = (nbrdf_query){{wi.x, wi.y, wi.z}, {wo.x, wo.y, wo.z}};
      weight[n] = li * wi.z / pdf;
      slot[n++] = k;
    }
    out->lost[s] = (double)lost / (double)total;
    if (n > 0) st = su->brdf(su->brdf_user, n, q, f, err);
    for (size_t j = 0; j < n && !st; j++)
      c[slot[j]] = f[j] * weight[j];
    if (st) break;
    double sum = 0.0;
    for (size_t k = 0; k < total; k++)
      sum += c[k];
    out->mean[s] = sum / (double)total;
    for (int k = 0; k < su->n_counts; k++)
      out->var[s][k] = rep_variance(c, su->reps, nmax, su->counts[k]);
    double v = rep_variance(c, su->reps, nmax, nmax) / su->reps;
    if (v > 0.0)
      wsum += 1.0 / v, wmean += out->mean[s] / v;
    else if (sum > 0.0)
      exact = out->mean[s];
  }
  out->radiance = exact >= 0.0 ? exact : (wsum > 0.0 ? wmean / wsum : 0.0);
  free(c), free(f), free(weight), free(slot), free(q);
  return st;
}
