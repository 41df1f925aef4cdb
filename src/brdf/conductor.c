#include "brdf/conductor.h"

#include "brdf/fresnel.h"
#include "brdf/ggx.h"

double bsdf_conductor_eval(const bsdf_conductor *c, vec3 wo, vec3 wi) {
  if (!(wo.z > 0.0) || !(wi.z > 0.0)) return 0.0;
  vec3 h = v3_add(wo, wi);
  double len = v3_length(h);
  if (!(len > 0.0)) return 0.0;
  h = v3_scale(h, 1.0 / len);
  double d = ggx_d(c->alpha, h);
  if (d == 0.0) return 0.0;
  double g = ggx_g2(c->alpha, wo, wi);
  double f = fresnel_schlick(c->r0, v3_dot(wo, h));
  return d * g * f / (4.0 * wo.z * wi.z);
}

double bsdf_conductor_pdf(const bsdf_conductor *c, vec3 wo, vec3 wi) {
  if (!(wo.z > 0.0) || !(wi.z > 0.0)) return 0.0;
  vec3 h = v3_add(wo, wi);
  double len = v3_length(h);
  if (!(len > 0.0)) return 0.0;
  h = v3_scale(h, 1.0 / len);
  /* D_wo(h) / (4 wo·h): the wo·h of the VNDF cancels the reflection Jacobian's. */
  return ggx_g1(c->alpha, wo) * ggx_d(c->alpha, h) / (4.0 * wo.z);
}

int bsdf_conductor_sample(const bsdf_conductor *c, vec3 wo, double u1, double u2,
                          bsdf_sample *s) {
  if (!(wo.z > 0.0)) return 0;
  vec3 m;
  if (!ggx_sample_vndf(c->alpha, wo, u1, u2, &m)) return 0;
  double wom = v3_dot(wo, m);
  if (!(wom > 0.0)) return 0;
  vec3 wi = fresnel_reflect(wo, m);
  if (!(wi.z > 0.0)) return 0; /* reflected below the horizon: masked in G2 */
  double d = ggx_d(c->alpha, m);
  double g1 = ggx_g1(c->alpha, wo), g2 = ggx_g2(c->alpha, wo, wi);
  double f = fresnel_schlick(c->r0, wom);
  s->wi = wi;
  s->pdf = g1 * d / (4.0 * wo.z);
  if (!(s->pdf > 0.0)) return 0;
  s->f = d * g2 * f / (4.0 * wo.z * wi.z);
  s->weight = f * g2 / g1;
  s->flags = BSDF_REFLECTION;
  return 1;
}
