#include "brdf/layered.h"

#include "brdf/dielectric.h"
#include "brdf/layered_walk.h"

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
  const double sigma_t = l->sigma_t;
  const int delta_top = top->eta == 1.0;

  brdf_bsdf_sample in;
  if (!brdf_bsdf_dielectric_sample_rng(top, wo, mode, BSDF_TRANSMISSION, rng, &in)) return 0.0;
  brdf_slab_walk s = brdf_slab_walk_start(l, mode, in.weight, in.wi);
  brdf_slab_exit ex;
  int have_exit = brdf_slab_exit_draw(&ex, l, wi, mode, rng);

  double sum = 0.0;
  for (;;) {
    brdf_slab_event at = brdf_slab_flight(&s, rng);
    if (at == BRDF_SLAB_END) break;
    if (at == BRDF_SLAB_MEDIUM) {
      if (have_exit) sum += brdf_slab_exit_medium(&ex, &s);
      brdf_slab_scatter(&s, rng);
      if (s.w.z > 0.0 && !delta_top)
        sum +=
            s.beta * exp(-sigma_t * s.z / s.w.z) * exit_term(top, s.w, wi, mode, BRDF_SLAB_INV_4PI);
    } else if (at == BRDF_SLAB_BOTTOM) {
      if (have_exit) sum += brdf_slab_exit_bottom(&ex, &s, mode, rng);
      brdf_bsdf_sample bs;
      if (!brdf_slab_bottom_bounce(&s, mode, rng, &bs)) break;
      if (!delta_top && !(bs.flags & BSDF_DELTA)) {
        double tr = sigma_t > 0.0 ? exp(-sigma_t / s.w.z) : 1.0;
        sum += s.beta * tr * exit_term(top, s.w, wi, mode, bs.pdf);
      }
    } else {
      /* Back at the top from inside: transmission out was accounted for by
       * the exit terms above, so only reflection continues the walk. An
       * index-matched top reflects nothing. */
      if (delta_top) break;
      brdf_bsdf_sample bs;
      if (!brdf_bsdf_dielectric_sample_rng(top, v3_neg(s.w), mode, BSDF_REFLECTION, rng, &bs))
        break;
      brdf_slab_bounce(&s, &bs);
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
