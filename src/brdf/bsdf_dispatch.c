#include "brdf/bsdf.h"

#include <stdlib.h>

#include "brdf/conductor.h"
#include "brdf/dielectric.h"
#include "brdf/layered.h"

double brdf_bsdf_eval(const brdf_bsdf *b, vec3 wo, vec3 wi, brdf_bsdf_mode mode, core_rng *rng) {
  switch (b->kind) {
  case BSDF_CONDUCTOR:
    return brdf_bsdf_conductor_eval(&b->conductor, wo, wi);
  case BSDF_DIELECTRIC:
    return brdf_bsdf_dielectric_eval(&b->dielectric, wo, wi, mode);
  case BSDF_LAYERED:
    return brdf_bsdf_layered_eval(&b->layered, wo, wi, mode, rng);
  }
  return 0.0;
}

int brdf_bsdf_sample_dir(const brdf_bsdf *b, vec3 wo, brdf_bsdf_mode mode, int flags, core_rng *rng,
                         brdf_bsdf_sample *s) {
  switch (b->kind) {
  case BSDF_CONDUCTOR:
    if (!(flags & BSDF_REFLECTION)) return 0;
    return brdf_bsdf_conductor_sample_rng(&b->conductor, wo, rng, s);
  case BSDF_DIELECTRIC:
    return brdf_bsdf_dielectric_sample_rng(&b->dielectric, wo, mode, flags, rng, s);
  case BSDF_LAYERED:
    if (!(flags & BSDF_REFLECTION)) return 0;
    return brdf_bsdf_layered_sample(&b->layered, wo, mode, rng, s);
  }
  return 0;
}

double brdf_bsdf_pdf(const brdf_bsdf *b, vec3 wo, vec3 wi, brdf_bsdf_mode mode, int flags) {
  (void)mode; /* no BSDF of the library has a mode-dependent sampler */
  switch (b->kind) {
  case BSDF_CONDUCTOR:
    return (flags & BSDF_REFLECTION) ? brdf_bsdf_conductor_pdf(&b->conductor, wo, wi) : 0.0;
  case BSDF_DIELECTRIC:
    return brdf_bsdf_dielectric_pdf(&b->dielectric, wo, wi, flags);
  case BSDF_LAYERED:
    return (flags & BSDF_REFLECTION) ? brdf_bsdf_layered_pdf(&b->layered, wo, wi) : 0.0;
  }
  return 0.0;
}

double brdf_bsdf_eval_pdf(const brdf_bsdf *b, vec3 wo, vec3 wi, brdf_bsdf_mode mode, int flags,
                          core_rng *rng, double *pdf) {
  if (b->kind == BSDF_CONDUCTOR) {
    double f = brdf_bsdf_conductor_eval_pdf(&b->conductor, wo, wi, pdf);
    if (!(flags & BSDF_REFLECTION)) *pdf = 0.0;
    return f;
  }
  *pdf = brdf_bsdf_pdf(b, wo, wi, mode, flags);
  return brdf_bsdf_eval(b, wo, wi, mode, rng);
}

int brdf_bsdf_is_stochastic(const brdf_bsdf *b) { return b->kind == BSDF_LAYERED; }

int brdf_bsdf_clone(brdf_bsdf *dst, const brdf_bsdf *src) {
  *dst = *src;
  if (src->kind != BSDF_LAYERED) return 1;
  dst->layered.bottom = NULL;
  brdf_bsdf *bottom = malloc(sizeof *bottom);
  if (!bottom) return 0;
  if (!brdf_bsdf_clone(bottom, src->layered.bottom)) {
    free(bottom);
    return 0;
  }
  dst->layered.bottom = bottom;
  return 1;
}

void brdf_bsdf_release(brdf_bsdf *b) {
  if (b->kind != BSDF_LAYERED || !b->layered.bottom) return;
  brdf_bsdf_release(b->layered.bottom);
  free(b->layered.bottom);
  b->layered.bottom = NULL;
}
