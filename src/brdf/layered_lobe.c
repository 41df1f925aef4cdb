#include "brdf/layered_lobe.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "brdf/dielectric.h"
#include "brdf/layered_walk.h"

/* Walks are summed in at most this many fixed chunks, in order, so that the
 * result does not depend on the thread count. */
#define MAX_CHUNKS 64

typedef struct lobe_walker {
  const brdf_bsdf_layered *l;
  size_t n;
  const vec3 *wo;
  brdf_slab_exit *ex; /* [n]: the exit sample towards each ωo_k, drawn once per walk */
  double *acc;
} lobe_walker;

/* The competing strategy of next-event estimation towards every ωo_k: the
 * vertex's own sampled direction w (density p_strategy) leaving through the
 * top, with transmittance tr. See exit_term in layered.c for the MIS pdf. */
static void splat_exit(lobe_walker *lw, vec3 w, double p_strategy, double scale) {
  vec3 ws = v3_neg(w);
  for (size_t k = 0; k < lw->n; k++) {
    double pe, fe = brdf_bsdf_dielectric_exit(&lw->l->top, ws, lw->wo[k], BSDF_RADIANCE, &pe);
    if (fe > 0.0) lw->acc[k] += scale * fe * brdf_bsdf_mis_power(p_strategy, pe);
  }
}

static void walk(lobe_walker *lw, vec3 wi, core_rng *rng) {
  const brdf_bsdf_layered *l = lw->l;
  const brdf_bsdf_dielectric *top = &l->top;
  const double sigma_t = l->sigma_t;
  const int delta_top = top->eta == 1.0;
  memset(lw->acc, 0, lw->n * sizeof *lw->acc);

  /* Radiance mode, as brdf_bsdf_layered_walk from ωi. */
  brdf_bsdf_sample in;
  if (!brdf_bsdf_dielectric_sample_rng(top, wi, BSDF_RADIANCE, BSDF_TRANSMISSION, rng, &in)) return;
  brdf_slab_walk s = brdf_slab_walk_start(l, BSDF_RADIANCE, in.weight, in.wi);
  for (size_t k = 0; k < lw->n; k++)
    brdf_slab_exit_draw(&lw->ex[k], l, lw->wo[k], BSDF_RADIANCE, rng);

  for (;;) {
    brdf_slab_event at = brdf_slab_flight(&s, rng);
    if (at == BRDF_SLAB_END) break;
    if (at == BRDF_SLAB_MEDIUM) {
      for (size_t k = 0; k < lw->n; k++)
        if (lw->ex[k].pdf > 0.0) lw->acc[k] += brdf_slab_exit_medium(&lw->ex[k], &s);
      brdf_slab_scatter(&s, rng);
      if (s.w.z > 0.0 && !delta_top)
        splat_exit(lw, s.w, BRDF_SLAB_INV_4PI, s.beta * exp(-sigma_t * s.z / s.w.z));
    } else if (at == BRDF_SLAB_BOTTOM) {
      for (size_t k = 0; k < lw->n; k++)
        if (lw->ex[k].pdf > 0.0)
          lw->acc[k] += brdf_slab_exit_bottom(&lw->ex[k], &s, BSDF_RADIANCE, rng);
      brdf_bsdf_sample bs;
      if (!brdf_slab_bottom_bounce(&s, BSDF_RADIANCE, rng, &bs)) break;
      if (!delta_top && !(bs.flags & BSDF_DELTA))
        splat_exit(lw, s.w, bs.pdf, s.beta * (sigma_t > 0.0 ? exp(-sigma_t / s.w.z) : 1.0));
    } else {
      if (delta_top) break;
      brdf_bsdf_sample bs;
      if (!brdf_bsdf_dielectric_sample_rng(top, v3_neg(s.w), BSDF_RADIANCE, BSDF_REFLECTION, rng,
                                           &bs))
        break;
      brdf_slab_bounce(&s, &bs);
    }
  }
}

/* 1: done; 0: out of memory; -1: stopped by the hook. */
static int lobe_eval(const brdf_bsdf_layered *l, vec3 wi, size_t n, const vec3 *wo, int walks,
                     uint64_t seed, int threads, const brdf_layered_lobe_hook *hook, double *f,
                     double *f_se) {
  if (n == 0) return 1;
  if (walks < 1) walks = 1;
  int chunk = (walks + MAX_CHUNKS - 1) / MAX_CHUNKS;
  int chunks = (walks + chunk - 1) / chunk;
  double *sums = calloc(2 * (size_t)chunks * n, sizeof *sums);
  if (!sums) return 0;
  int nt = threads > 0 ? threads : omp_get_max_threads();
  int failed = 0, halted = 0;
#pragma omp parallel num_threads(nt)
  {
    lobe_walker lw = {l, n, wo, malloc(n * sizeof(brdf_slab_exit)), malloc(n * sizeof(double))};
    if (!lw.ex || !lw.acc) {
#pragma omp atomic write
      failed = 1;
    }
#pragma omp for schedule(dynamic, 1)
    for (int c = 0; c < chunks; c++) {
      int h;
#pragma omp atomic read
      h = halted;
      if (!lw.ex || !lw.acc || h) continue;
      double *s1 = sums + 2 * (size_t)c * n, *s2 = s1 + n;
      int end = (c + 1) * chunk < walks ? (c + 1) * chunk : walks;
      for (int j = c * chunk; j < end; j++) {
        /* a chunk holds walks / 64 walks: with many walks, seconds; the hook
         * is asked every 8 walks (the calling thread, 0 of the team, ticks) */
        if (hook && (j - c * chunk) % 8 == 0) {
          int stop = (hook->stop && *hook->stop) ||
                     (omp_get_thread_num() == 0 && hook->tick && hook->tick(hook->user));
          if (stop) {
#pragma omp atomic write
            halted = 1;
          }
#pragma omp atomic read
          stop = halted;
          if (stop) break;
        }
        core_rng rng;
        core_rng_init(&rng, seed, (uint64_t)j);
        walk(&lw, wi, &rng);
        for (size_t k = 0; k < n; k++) {
          s1[k] += lw.acc[k];
          s2[k] += lw.acc[k] * lw.acc[k];
        }
      }
    }
    free(lw.ex);
    free(lw.acc);
  }
  if (failed || halted) {
    free(sums);
    return failed ? 0 : -1;
  }
  for (size_t k = 0; k < n; k++) {
    double s1 = 0.0, s2 = 0.0;
    for (int c = 0; c < chunks; c++) {
      s1 += sums[2 * (size_t)c * n + k];
      s2 += sums[(2 * (size_t)c + 1) * n + k];
    }
    double mean = s1 / walks;
    /* The top's own reflection is exact: it moves the mean, not the error. */
    f[k] = brdf_bsdf_dielectric_eval(&l->top, wi, wo[k], BSDF_RADIANCE) + mean;
    if (f_se)
      f_se[k] =
          walks > 1 ? sqrt(fmax(0.0, s2 - s1 * mean) / ((double)(walks - 1) * walks)) : INFINITY;
  }
  free(sums);
  return 1;
}

int brdf_layered_lobe_eval(const brdf_bsdf_layered *l, vec3 wi, size_t n, const vec3 *wo, int walks,
                           uint64_t seed, int threads, double *f, double *f_se) {
  return lobe_eval(l, wi, n, wo, walks, seed, threads, NULL, f, f_se);
}

int brdf_layered_lobe_eval_hooked(const brdf_bsdf_layered *l, vec3 wi, size_t n, const vec3 *wo,
                                  int walks, uint64_t seed, int threads,
                                  const brdf_layered_lobe_hook *hook, double *f, double *f_se) {
  return lobe_eval(l, wi, n, wo, walks, seed, threads, hook, f, f_se);
}

int brdf_layered_lobe_image(const brdf_bsdf_layered *l, double theta_i, int res, int walks,
                            uint64_t seed, int threads, double *image, double *image_se) {
  return brdf_layered_lobe_image_hooked(l, theta_i, res, walks, seed, threads, NULL, image,
                                        image_se);
}

int brdf_layered_lobe_image_hooked(const brdf_bsdf_layered *l, double theta_i, int res, int walks,
                                   uint64_t seed, int threads, const brdf_layered_lobe_hook *hook,
                                   double *image, double *image_se) {
  size_t npix = (size_t)res * res, n = 0;
  vec3 *wo = calloc(npix, sizeof *wo);
  size_t *at = malloc(npix * sizeof *at);
  double *f = malloc(npix * sizeof *f), *se = malloc(npix * sizeof *se);
  int ok = wo && at && f && se;
  if (ok) {
    for (int row = 0; row < res; row++)
      for (int col = 0; col < res; col++) {
        double x = -1.0 + (col + 0.5) * 2.0 / res, y = 1.0 - (row + 0.5) * 2.0 / res;
        double r2 = x * x + y * y;
        image[row * res + col] = 0.0;
        if (image_se) image_se[row * res + col] = 0.0;
        if (r2 >= 1.0) continue;
        wo[n] = v3(x, y, sqrt(1.0 - r2));
        at[n++] = (size_t)row * res + col;
      }
    vec3 wi = v3(sin(theta_i), 0.0, cos(theta_i));
    ok = lobe_eval(l, wi, n, wo, walks, seed, threads, hook, f, se);
    for (size_t k = 0; ok == 1 && k < n; k++) {
      image[at[k]] = f[k] * wo[k].z;
      if (image_se) image_se[at[k]] = se[k] * wo[k].z;
    }
  }
  free(wo);
  free(at);
  free(f);
  free(se);
  return ok;
}
