#include "brdf/conductor.h"

#include "brdf/disk.h"
#include "brdf/fresnel.h"
#include "brdf/ggx.h"

double brdf_bsdf_conductor_eval_pdf(const brdf_bsdf_conductor *c, vec3 wo, vec3 wi, double *pdf) {
  *pdf = 0.0;
  if (!(wo.z > 0.0) || !(wi.z > 0.0)) return 0.0;
  vec3 h = v3_add(wo, wi);
  double len = v3_length(h);
  if (!(len > 0.0)) return 0.0;
  h = v3_scale(h, 1.0 / len);
  double d = brdf_ggx_d(c->alpha, h);
  if (d == 0.0) return 0.0;
  double lo = brdf_ggx_lambda(c->alpha, wo), li = brdf_ggx_lambda(c->alpha, wi);
  /* D_wo(h) / (4 wo·h): the wo·h of the VNDF cancels the reflection Jacobian's. */
  *pdf = d / ((1.0 + lo) * 4.0 * wo.z);
  double f = brdf_fresnel_schlick(c->r0, v3_dot(wo, h));
  return d * f / ((1.0 + lo + li) * 4.0 * wo.z * wi.z);
}

double brdf_bsdf_conductor_eval(const brdf_bsdf_conductor *c, vec3 wo, vec3 wi) {
  double pdf;
  return brdf_bsdf_conductor_eval_pdf(c, wo, wi, &pdf);
}

double brdf_bsdf_conductor_pdf(const brdf_bsdf_conductor *c, vec3 wo, vec3 wi) {
  double pdf;
  brdf_bsdf_conductor_eval_pdf(c, wo, wi, &pdf);
  return pdf;
}

/* Reflection about a sampled visible normal m. */
static int reflect_normal(const brdf_bsdf_conductor *c, vec3 wo, vec3 m, brdf_bsdf_sample *s) {
  double wom = v3_dot(wo, m);
  if (!(wom > 0.0)) return 0;
  vec3 wi = brdf_fresnel_reflect(wo, m);
  if (!(wi.z > 0.0)) return 0; /* reflected below the horizon: masked in G2 */
  double d = brdf_ggx_d(c->alpha, m);
  double lo = brdf_ggx_lambda(c->alpha, wo), li = brdf_ggx_lambda(c->alpha, wi);
  double f = brdf_fresnel_schlick(c->r0, wom);
  s->wi = wi;
  s->pdf = d / ((1.0 + lo) * 4.0 * wo.z);
  if (!(s->pdf > 0.0)) return 0;
  s->f = d * f / ((1.0 + lo + li) * 4.0 * wo.z * wi.z);
  s->weight = f * (1.0 + lo) / (1.0 + lo + li); /* F G2 / G1 */
  s->flags = BSDF_REFLECTION;
  return 1;
}

int brdf_bsdf_conductor_sample(const brdf_bsdf_conductor *c, vec3 wo, double u1, double u2,
                               brdf_bsdf_sample *s) {
  vec3 m;
  if (!(wo.z > 0.0) || !brdf_ggx_sample_vndf(c->alpha, wo, u1, u2, &m)) return 0;
  return reflect_normal(c, wo, m, s);
}

int brdf_bsdf_conductor_sample_rng(const brdf_bsdf_conductor *c, vec3 wo, core_rng *rng,
                                   brdf_bsdf_sample *s) {
  if (!(wo.z > 0.0)) return 0;
  double x, y, r2;
  brdf_disk_sample(rng, &x, &y, &r2);
  vec3 m;
  if (!brdf_ggx_sample_vndf_disk(c->alpha, wo, x, y, r2, &m)) return 0;
  return reflect_normal(c, wo, m, s);
}
