#include "brdf/dielectric.h"
#include "brdf/disk.h"
#include "brdf/fresnel.h"
#include "brdf/layered.h"

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
  const brdf_bsdf_dielectric *top = &l->top;
  const double sigma_t = l->sigma_t, albedo = l->albedo;
  const int scattering = sigma_t > 0.0 && albedo > 0.0;
  const double rr_scale = mode == BSDF_RADIANCE ? top->eta * top->eta : 1.0;

  brdf_bsdf_sample bs;
  if (!brdf_bsdf_dielectric_sample_rng(top, wo, mode, BSDF_ALL, rng, &bs)) return 0;
  if (bs.flags & BSDF_REFLECTION) return finish(l, wo, bs.wi, bs.weight, s);
  double beta = bs.weight;
  vec3 w = bs.wi;
  double z = 0.0;
  for (int vertex = 0;; vertex++) {
    if (!brdf_bsdf_layered_roulette(&beta, rr_scale, vertex, rng)) return 0;
    if (scattering) {
      double t = -log(1.0 - core_rng_uniform(rng)) / sigma_t;
      double zn = z - t * w.z;
      if (zn > 0.0 && zn < 1.0) {
        z = zn;
        beta *= albedo;
        double x, y, r2;
        brdf_disk_sample(rng, &x, &y, &r2);
        w = brdf_disk_to_sphere(x, y, r2);
        continue;
      }
      z = zn <= 0.0 ? 0.0 : 1.0;
    } else {
      if (sigma_t > 0.0) beta *= exp(-sigma_t / fabs(w.z));
      z = w.z < 0.0 ? 1.0 : 0.0;
    }
    if (z == 1.0) {
      if (!brdf_bsdf_sample_dir(l->bottom, v3_neg(w), mode, BSDF_REFLECTION, rng, &bs)) return 0;
      if (!(bs.wi.z > 0.0)) return 0;
    } else {
      if (!brdf_bsdf_dielectric_sample_rng(top, v3_neg(w), mode, BSDF_ALL, rng, &bs)) return 0;
    }
    beta *= bs.weight;
    w = bs.wi;
    if (z == 0.0 && (bs.flags & BSDF_TRANSMISSION)) return finish(l, wo, w, beta, s);
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
