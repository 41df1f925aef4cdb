#include "brdf/dielectric.h"

#include "brdf/disk.h"
#include "brdf/fresnel.h"
#include "brdf/ggx.h"

/* The (generalised) half vector of a pair of directions (Walter eq. 13 and 16:
 * m ∝ η' wi + wo, with η' = η_wi / η_wo, 1 for reflection), flipped into the
 * upper hemisphere. Returns 0 for grazing or degenerate pairs and for
 * back-facing microfacets (wo and wi must each lie on m's side that their own
 * hemisphere faces). */
static int half_vector(const brdf_bsdf_dielectric *d, vec3 wo, vec3 wi, vec3 *m, double *etap) {
  if (wo.z == 0.0 || wi.z == 0.0) return 0;
  double e = 1.0;
  if (wo.z * wi.z < 0.0) e = wo.z > 0.0 ? d->eta : 1.0 / d->eta;
  vec3 h = v3_add(v3_scale(wi, e), wo);
  double len2 = v3_dot(h, h);
  if (!(len2 > 0.0)) return 0;
  h = v3_scale(h, 1.0 / sqrt(len2));
  if (h.z < 0.0) h = v3_neg(h);
  if (!(v3_dot(h, wi) * wi.z > 0.0) || !(v3_dot(h, wo) * wo.z > 0.0)) return 0;
  *m = h;
  *etap = e;
  return 1;
}

double brdf_bsdf_dielectric_eval(const brdf_bsdf_dielectric *d, vec3 wo, vec3 wi,
                                 brdf_bsdf_mode mode) {
  if (d->eta == 1.0) return 0.0;
  vec3 m;
  double etap;
  if (!half_vector(d, wo, wi, &m, &etap)) return 0.0;
  double dm = brdf_ggx_d(d->alpha, m);
  if (dm == 0.0) return 0.0;
  double g = brdf_ggx_g2(d->alpha, wo, wi);
  double wom = v3_dot(wo, m), wim = v3_dot(wi, m);
  double fr = brdf_fresnel_dielectric(wom, d->eta);
  double cos2 = fabs(wo.z * wi.z);
  if (wo.z * wi.z > 0.0) return dm * g * fr / (4.0 * cos2);
  double s = wim + wom / etap;
  double denom = s * s * cos2;
  if (!(denom > 0.0)) return 0.0;
  double ft = dm * (1.0 - fr) * g * fabs(wim * wom) / denom;
  if (mode == BSDF_RADIANCE) ft /= etap * etap;
  return ft;
}

double brdf_bsdf_dielectric_pdf(const brdf_bsdf_dielectric *d, vec3 wo, vec3 wi, int flags) {
  if (d->eta == 1.0) return 0.0;
  vec3 m;
  double etap;
  if (!half_vector(d, wo, wi, &m, &etap)) return 0.0;
  int reflect = wo.z * wi.z > 0.0;
  if (!(flags & (reflect ? BSDF_REFLECTION : BSDF_TRANSMISSION))) return 0.0;
  double wom = v3_dot(wo, m), wim = v3_dot(wi, m);
  double fr = brdf_fresnel_dielectric(wom, d->eta);
  double pr = (flags & BSDF_REFLECTION) ? fr : 0.0;
  double pt = (flags & BSDF_TRANSMISSION) ? 1.0 - fr : 0.0;
  if (!(pr + pt > 0.0)) return 0.0;
  double vndf = brdf_ggx_vndf_pdf(d->alpha, wo, m);
  if (reflect) return vndf / (4.0 * fabs(wom)) * (pr / (pr + pt));
  double s = wim + wom / etap;
  if (!(s != 0.0)) return 0.0;
  return vndf * fabs(wim) / (s * s) * (pt / (pr + pt));
}

double brdf_bsdf_dielectric_exit(const brdf_bsdf_dielectric *d, vec3 ws, vec3 wi,
                                 brdf_bsdf_mode mode, double *pdf_from_wi) {
  *pdf_from_wi = 0.0;
  if (d->eta == 1.0 || !(ws.z < 0.0) || !(wi.z > 0.0)) return 0.0;
  vec3 m;
  double etap; /* η_wi / η_ws = 1/η */
  if (!half_vector(d, ws, wi, &m, &etap)) return 0.0;
  double dm = brdf_ggx_d(d->alpha, m);
  if (dm == 0.0) return 0.0;
  double wsm = v3_dot(ws, m), wim = v3_dot(wi, m);
  double t = 1.0 - brdf_fresnel_dielectric(wim, d->eta);
  double ls = brdf_ggx_lambda(d->alpha, ws), li = brdf_ggx_lambda(d->alpha, wi);
  double s = wim + wsm / etap;     /* Jacobian term seen from ws */
  double s_rev = wsm + wim * etap; /* … and from wi (η' = η) */
  if (!(s != 0.0) || !(s_rev != 0.0)) return 0.0;
  /* pdf(ws | wi) = D_wi(m) |ws·m| / (ws·m + wi·m/η)², D_wi(m) = G1(wi) (wi·m) D / cos θi. */
  *pdf_from_wi = dm * wim / ((1.0 + li) * wi.z) * fabs(wsm) / (s_rev * s_rev);
  double ft = dm * t * fabs(wim * wsm) / ((1.0 + ls + li) * s * s * fabs(ws.z * wi.z));
  if (mode == BSDF_RADIANCE) ft /= etap * etap;
  return ft;
}

static int sample_delta(vec3 wo, int flags, brdf_bsdf_sample *s) {
  if (!(flags & BSDF_TRANSMISSION) || wo.z == 0.0) return 0;
  s->wi = v3_neg(wo);
  s->f = 1.0 / fabs(wo.z);
  s->pdf = 1.0;
  s->weight = 1.0;
  s->flags = BSDF_TRANSMISSION | BSDF_DELTA;
  return 1;
}

/* Reflection or refraction about a visible normal m sampled for wo. */
static int scatter(const brdf_bsdf_dielectric *d, vec3 wo, brdf_bsdf_mode mode, int flags,
                   double uc, vec3 m, brdf_bsdf_sample *s) {
  double wom = v3_dot(wo, m);
  if (!(wom * wo.z > 0.0)) return 0;
  double fr = brdf_fresnel_dielectric(wom, d->eta);
  double pr = (flags & BSDF_REFLECTION) ? fr : 0.0;
  double pt = (flags & BSDF_TRANSMISSION) ? 1.0 - fr : 0.0;
  if (!(pr + pt > 0.0)) return 0;
  double lo = brdf_ggx_lambda(d->alpha, wo);
  double dm = brdf_ggx_d(d->alpha, m);
  double vndf = fabs(wom) * dm / ((1.0 + lo) * fabs(wo.z)); /* D_wo(m) */
  if (!(vndf > 0.0)) return 0;
  vec3 wi;
  if (uc * (pr + pt) < pr) {
    wi = brdf_fresnel_reflect(wo, m);
    if (!(wi.z * wo.z > 0.0)) return 0;
    double p = pr / (pr + pt);
    double g2 = 1.0 / (1.0 + lo + brdf_ggx_lambda(d->alpha, wi));
    s->wi = wi;
    s->pdf = vndf / (4.0 * fabs(wom)) * p;
    s->f = dm * g2 * fr / (4.0 * fabs(wo.z * wi.z));
    s->weight = fr * g2 * (1.0 + lo) / p; /* F G2 / (G1 p) */
    s->flags = BSDF_REFLECTION;
  } else {
    double etap;
    if (!brdf_fresnel_refract(wo, m, d->eta, &wi, &etap)) return 0;
    if (!(wi.z * wo.z < 0.0)) return 0;
    double p = pt / (pr + pt);
    double g2 = 1.0 / (1.0 + lo + brdf_ggx_lambda(d->alpha, wi));
    double wim = v3_dot(wi, m);
    double sum = wim + wom / etap;
    double scale = mode == BSDF_RADIANCE ? 1.0 / (etap * etap) : 1.0;
    s->wi = wi;
    s->pdf = vndf * fabs(wim) / (sum * sum) * p;
    if (!(s->pdf > 0.0) || !isfinite(s->pdf)) return 0;
    s->f = dm * (1.0 - fr) * g2 * fabs(wim * wom) / (sum * sum * fabs(wo.z * wi.z)) * scale;
    s->weight = (1.0 - fr) * g2 * (1.0 + lo) / p * scale;
    s->flags = BSDF_TRANSMISSION;
  }
  return 1;
}

int brdf_bsdf_dielectric_sample(const brdf_bsdf_dielectric *d, vec3 wo, brdf_bsdf_mode mode,
                                int flags, double uc, double u1, double u2, brdf_bsdf_sample *s) {
  if (d->eta == 1.0) return sample_delta(wo, flags, s);
  vec3 m;
  if (wo.z == 0.0 || !brdf_ggx_sample_vndf(d->alpha, wo, u1, u2, &m)) return 0;
  return scatter(d, wo, mode, flags, uc, m, s);
}

int brdf_bsdf_dielectric_sample_rng(const brdf_bsdf_dielectric *d, vec3 wo, brdf_bsdf_mode mode,
                                    int flags, core_rng *rng, brdf_bsdf_sample *s) {
  if (d->eta == 1.0) return sample_delta(wo, flags, s);
  if (wo.z == 0.0) return 0;
  double uc = (flags & BSDF_ALL) == BSDF_ALL ? core_rng_uniform(rng) : 0.0;
  double x, y, r2;
  brdf_disk_sample(rng, &x, &y, &r2);
  vec3 m;
  if (!brdf_ggx_sample_vndf_disk(d->alpha, wo, x, y, r2, &m)) return 0;
  return scatter(d, wo, mode, flags, uc, m, s);
}
