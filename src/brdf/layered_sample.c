#include "brdf/dielectric.h"
#include "brdf/fresnel.h"
#include "brdf/layered.h"
#include "brdf/layered_walk.h"

static int finish(const brdf_bsdf_layered *l, vec3 wo, vec3 wi, double weight,
                  brdf_bsdf_sample *s) {
  if (!(wi.z > 0.0)) return 0;
  s->wi = wi;
  s->weight = weight;
  s->pdf = brdf_bsdf_layered_pdf(l, wo, wi);
  s->f = s->pdf > 0.0 ? weight * s->pdf / wi.z : 0.0;
  s->flags = BSDF_REFLECTION;
  return 1;
}

int brdf_bsdf_layered_sample(const brdf_bsdf_layered *l, vec3 wo, brdf_bsdf_mode mode,
                             core_rng *rng, brdf_bsdf_sample *s) {
  if (!(wo.z > 0.0)) return 0;
  brdf_bsdf_sample bs;
  if (!brdf_bsdf_dielectric_sample_rng(&l->top, wo, mode, BSDF_ALL, rng, &bs)) return 0;
  if (bs.flags & BSDF_REFLECTION) return finish(l, wo, bs.wi, bs.weight, s);
  brdf_slab_walk w = brdf_slab_walk_start(l, mode, bs.weight, bs.wi);
  for (;;) {
    brdf_slab_event at = brdf_slab_flight(&w, rng);
    if (at == BRDF_SLAB_END) return 0;
    if (at == BRDF_SLAB_MEDIUM) {
      brdf_slab_scatter(&w, rng);
    } else if (at == BRDF_SLAB_BOTTOM) {
      if (!brdf_slab_bottom_bounce(&w, mode, rng, &bs)) return 0;
    } else {
      /* At the top from inside: out through it (the sample), or back in. */
      if (!brdf_bsdf_dielectric_sample_rng(&l->top, v3_neg(w.w), mode, BSDF_ALL, rng, &bs))
        return 0;
      brdf_slab_bounce(&w, &bs);
      if (bs.flags & BSDF_TRANSMISSION) return finish(l, wo, w.w, w.beta, s);
    }
  }
}

double brdf_bsdf_layered_pdf(const brdf_bsdf_layered *l, vec3 wo, vec3 wi) {
  if (!(wo.z > 0.0) || !(wi.z > 0.0)) return 0.0;
  /* The top's specular lobe, weighted by its Fresnel reflectance at the
   * macro normal, plus a cosine lobe for everything that went through the
   * slab. Crude on purpose: it only shapes MIS weights (bsdf.h). */
  double diffuse = wi.z / M_PI;
  if (l->top.eta == 1.0) return diffuse;
  double c = brdf_fresnel_dielectric(wo.z, l->top.eta);
  return c * brdf_bsdf_dielectric_pdf(&l->top, wo, wi, BSDF_REFLECTION) + (1.0 - c) * diffuse;
}
