#include "brdf/layered.h"

#include "brdf/dielectric.h"
#include "brdf/disk.h"

#define INV_4PI (1.0 / (4.0 * M_PI)) /* isotropic phase function */

/* Survivors of the roulette carry about this throughput. 0.25 measured best
 * in walks/s ÷ variance over bench/bench_walk.c's three BRDFs (0.1 .. 1). */
#define RR_THRESHOLD 0.25
/* Past this many vertices every walk also survives with at most this
 * probability, so that walks in lossless media (A = 1 over a white bottom,
 * σT = 1000) still end in finite expected time. Unbiased, unlike a cap. */
#define RR_LONG_WALK 512
#define RR_LONG_SURVIVAL 0.99

int brdf_bsdf_layered_roulette(double *beta, double scale, int vertex, core_rng *rng) {
  double q = *beta * scale / RR_THRESHOLD;
  if (vertex > RR_LONG_WALK) q = fmin(q, RR_LONG_SURVIVAL);
  if (q >= 1.0) return 1;
  if (!(q > 0.0)) return 0;
  if (core_rng_uniform(rng) >= q) return 0;
  *beta /= q;
  return 1;
}

/* The competing strategy to next-event estimation: a direction w (travelling
 * up inside the slab) drawn by phase or bottom sampling with density
 * p_strategy leaves through the top towards wi. Its MIS partner is the exit
 * sample, which draws the inner direction ws = −w from the OUTSIDE direction
 * wi (adjoint transport), so the partner density is the transmission pdf
 * from wi towards ws — not the pdf of wi given ws, whose weights would not
 * sum to one with η ≠ 1 (ECOSYSTEM-NOTES.md, pitfall 1). */
static double exit_term(const brdf_bsdf_dielectric *top, vec3 w, vec3 wi, brdf_bsdf_mode mode,
                        double p_strategy) {
  double pe;
  double fe = brdf_bsdf_dielectric_exit(top, v3_neg(w), wi, mode, &pe);
  if (!(fe > 0.0)) return 0.0;
  return fe * brdf_bsdf_mis_power(p_strategy, pe);
}

double brdf_bsdf_layered_walk(const brdf_bsdf_layered *l, vec3 wo, vec3 wi, brdf_bsdf_mode mode,
                              core_rng *rng) {
  if (!(wo.z > 0.0) || !(wi.z > 0.0)) return 0.0;
  const brdf_bsdf_dielectric *top = &l->top;
  const brdf_bsdf *bottom = l->bottom;
  const double sigma_t = l->sigma_t, albedo = l->albedo;
  const int delta_top = top->eta == 1.0;
  const int scattering = sigma_t > 0.0 && albedo > 0.0;
  const double rr_scale = mode == BSDF_RADIANCE ? top->eta * top->eta : 1.0;

  brdf_bsdf_sample in;
  if (!brdf_bsdf_dielectric_sample_rng(top, wo, mode, BSDF_TRANSMISSION, rng, &in)) return 0.0;
  double beta = in.weight;
  vec3 w = in.wi;

  /* The exit sample for next-event estimation, drawn once per walk: an inner
   * direction ws from wi in the adjoint mode, so that ex.f = f_adj(wi, ws) =
   * f(ws, wi) is the transmission out towards wi. Light reaches the exit
   * travelling along `up` = −ws. */
  brdf_bsdf_sample ex = {0};
  int have_exit = brdf_bsdf_dielectric_sample_rng(top, wi, brdf_bsdf_adjoint(mode),
                                                  BSDF_TRANSMISSION, rng, &ex);
  double ex_cos = have_exit ? fabs(ex.wi.z) : 1.0;
  double ex_ratio = have_exit ? ex.f / ex.pdf : 0.0; /* Dirac exit: 1 / |cos| */
  vec3 up = v3_neg(ex.wi);
  double ex_tr_slab = have_exit && sigma_t > 0.0 ? exp(-sigma_t / ex_cos) : 1.0;
  /* At a medium vertex the partner strategy is the phase function's 1/4π. */
  double nee_medium = have_exit ? albedo * INV_4PI * ex_ratio *
                                      (delta_top ? 1.0 : brdf_bsdf_mis_power(ex.pdf, INV_4PI))
                                : 0.0;

  double sum = 0.0, z = 0.0; /* z: depth below the top, 0..1 */
  for (int vertex = 0;; vertex++) {
    if (!brdf_bsdf_layered_roulette(&beta, rr_scale, vertex, rng)) break;
    if (scattering) {
      /* Free flight: optical distance ~ Exp(1), depth changes by t |cos θ|. */
      double t = -log(1.0 - core_rng_uniform(rng)) / sigma_t;
      double zn = z - t * w.z;
      if (zn > 0.0 && zn < 1.0) {
        z = zn;
        if (have_exit) sum += beta * nee_medium * exp(-sigma_t * z / ex_cos);
        beta *= albedo; /* isotropic phase sampled exactly: p / pdf = 1 */
        double x, y, r2;
        brdf_disk_sample(rng, &x, &y, &r2);
        w = brdf_disk_to_sphere(x, y, r2);
        if (w.z > 0.0 && !delta_top)
          sum += beta * exp(-sigma_t * z / w.z) * exit_term(top, w, wi, mode, INV_4PI);
        continue;
      }
      z = zn <= 0.0 ? 0.0 : 1.0;
    } else {
      if (sigma_t > 0.0) beta *= exp(-sigma_t / fabs(w.z)); /* pure absorber */
      z = w.z < 0.0 ? 1.0 : 0.0;
    }

    if (z == 1.0) {
      vec3 wb = v3_neg(w); /* the bottom's wo */
      if (have_exit) {
        double pb, fb = brdf_bsdf_eval_pdf(bottom, wb, up, mode, BSDF_REFLECTION, rng, &pb);
        double wt = delta_top ? 1.0 : brdf_bsdf_mis_power(ex.pdf, pb);
        sum += beta * fb * ex_cos * wt * ex_tr_slab * ex_ratio;
      }
      brdf_bsdf_sample bs;
      if (!brdf_bsdf_sample_dir(bottom, wb, mode, BSDF_REFLECTION, rng, &bs)) break;
      if (!(bs.wi.z > 0.0)) break;
      beta *= bs.weight;
      w = bs.wi;
      if (!delta_top && !(bs.flags & BSDF_DELTA)) {
        double tr = sigma_t > 0.0 ? exp(-sigma_t / w.z) : 1.0;
        sum += beta * tr * exit_term(top, w, wi, mode, bs.pdf);
      }
    } else {
      /* Back at the top from inside: transmission out was accounted for by
       * the exit terms above, so only reflection continues the walk. An
       * index-matched top reflects nothing. */
      if (delta_top) break;
      brdf_bsdf_sample bs;
      if (!brdf_bsdf_dielectric_sample_rng(top, v3_neg(w), mode, BSDF_REFLECTION, rng, &bs)) break;
      beta *= bs.weight;
      w = bs.wi;
    }
  }
  return sum;
}

double brdf_bsdf_layered_eval(const brdf_bsdf_layered *l, vec3 wo, vec3 wi, brdf_bsdf_mode mode,
                              core_rng *rng) {
  if (!(wo.z > 0.0) || !(wi.z > 0.0)) return 0.0;
  return brdf_bsdf_dielectric_eval(&l->top, wo, wi, mode) +
         brdf_bsdf_layered_walk(l, wo, wi, mode, rng);
}
