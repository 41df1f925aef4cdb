#include "brdf/conductor.h"

#include "brdf/disk.h"
#include "brdf/fresnel.h"
#include "brdf/ggx.h"

double bsdf_conductor_eval_pdf(const bsdf_conductor *c, vec3 wo, vec3 wi, double *pdf) {
  *pdf = 0.0;
  if (!(wo.z > 0.0) || !(wi.z > 0.0)) return 0.0;
  vec3 h = v3_add(wo, wi);
  double len = v3_length(h);
  if (!(len > 0.0)) return 0.0;
  h = v3_scale(h, 1.0 / len);
  double d = ggx_d(c->alpha, h);
  if (d == 0.0) return 0.0;
  double lo = ggx_lambda(c->alpha, wo), li = ggx_lambda(c->alpha, wi);
  /* D_wo(h) / (4 wo·h): the wo·h of the VNDF cancels the reflection Jacobian's. */
  *pdf = d / ((1.0 + lo) * 4.0 * wo.z);
  double f = fresnel_schlick(c->r0, v3_dot(wo, h));
  return d * f / ((1.0 + lo + li) * 4.0 * wo.z * wi.z);
}

double bsdf_conductor_eval(const bsdf_conductor *c, vec3 wo, vec3 wi) {
  double pdf;
  return bsdf_conductor_eval_pdf(c, wo, wi, &pdf);
}

double bsdf_conductor_pdf(const bsdf_conductor *c, vec3 wo, vec3 wi) {
  double pdf;
  bsdf_conductor_eval_pdf(c, wo, wi, &pdf);
  return pdf;
}

/* Reflection about a sampled visible normal m. */
static int reflect_normal(const bsdf_conductor *c, vec3 wo, vec3 m, bsdf_sample *s) {
  double wom = v3_dot(wo, m);
  if (!(wom > 0.0)) return 0;
  vec3 wi = fresnel_reflect(wo, m);
  if (!(wi.z > 0.0)) return 0; /* reflected below the horizon: masked in G2 */
  double d = ggx_d(c->alpha, m);
  double lo = ggx_lambda(c->alpha, wo), li = ggx_lambda(c->alpha, wi);
  double f = fresnel_schlick(c->r0, wom);
  s->wi = wi;
  s->pdf = d / ((1.0 + lo) * 4.0 * wo.z);
  if (!(s->pdf > 0.0)) return 0;
  s->f = d * f / ((1.0 + lo + li) * 4.0 * wo.z * wi.z);
  s->weight = f * (1.0 + lo) / (1.0 + lo + li); /* F G2 / G1 */
  s->flags = BSDF_REFLECTION;
  return 1;
}

int bsdf_conductor_sample(const bsdf_conductor *c, vec3 wo, double u1, double u2, bsdf_sample *s) {
  vec3 m;
  if (!(wo.z > 0.0) || !ggx_sample_vndf(c->alpha, wo, u1, u2, &m)) return 0;
  return reflect_normal(c, wo, m, s);
}

int bsdf_conductor_sample_rng(const bsdf_conductor *c, vec3 wo, core_rng *rng, bsdf_sample *s) {
  if (!(wo.z > 0.0)) return 0;
  double x, y, r2;
  disk_sample(rng, &x, &y, &r2);
  vec3 m;
  if (!ggx_sample_vndf_disk(c->alpha, wo, x, y, r2, &m)) return 0;
  return reflect_normal(c, wo, m, s);
}
