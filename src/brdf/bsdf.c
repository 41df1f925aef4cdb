#include "brdf/bsdf.h"

#include <stdlib.h>

#include "brdf/conductor.h"
#include "brdf/dielectric.h"
#include "brdf/layered.h"

double bsdf_eval(const bsdf *b, vec3 wo, vec3 wi, bsdf_mode mode, core_rng *rng) {
  switch (b->kind) {
  case BSDF_CONDUCTOR:
    return bsdf_conductor_eval(&b->conductor, wo, wi);
  case BSDF_DIELECTRIC:
    return bsdf_dielectric_eval(&b->dielectric, wo, wi, mode);
  case BSDF_LAYERED:
    return bsdf_layered_eval(&b->layered, wo, wi, mode, rng);
  }
  return 0.0;
}

int bsdf_sample_dir(const bsdf *b, vec3 wo, bsdf_mode mode, int flags, core_rng *rng,
                    bsdf_sample *s) {
  switch (b->kind) {
  case BSDF_CONDUCTOR:
    if (!(flags & BSDF_REFLECTION)) return 0;
    return bsdf_conductor_sample_rng(&b->conductor, wo, rng, s);
  case BSDF_DIELECTRIC:
    return bsdf_dielectric_sample_rng(&b->dielectric, wo, mode, flags, rng, s);
  case BSDF_LAYERED:
    if (!(flags & BSDF_REFLECTION)) return 0;
    return bsdf_layered_sample(&b->layered, wo, mode, rng, s);
  }
  return 0;
}

double bsdf_pdf(const bsdf *b, vec3 wo, vec3 wi, bsdf_mode mode, int flags) {
  (void)mode; /* no BSDF of the library has a mode-dependent sampler */
  switch (b->kind) {
  case BSDF_CONDUCTOR:
    return (flags & BSDF_REFLECTION) ? bsdf_conductor_pdf(&b->conductor, wo, wi) : 0.0;
  case BSDF_DIELECTRIC:
    return bsdf_dielectric_pdf(&b->dielectric, wo, wi, flags);
  case BSDF_LAYERED:
    return (flags & BSDF_REFLECTION) ? bsdf_layered_pdf(&b->layered, wo, wi) : 0.0;
  }
  return 0.0;
}

double bsdf_eval_pdf(const bsdf *b, vec3 wo, vec3 wi, bsdf_mode mode, int flags, core_rng *rng,
                     double *pdf) {
  if (b->kind == BSDF_CONDUCTOR) {
    double f = bsdf_conductor_eval_pdf(&b->conductor, wo, wi, pdf);
    if (!(flags & BSDF_REFLECTION)) *pdf = 0.0;
    return f;
  }
  *pdf = bsdf_pdf(b, wo, wi, mode, flags);
  return bsdf_eval(b, wo, wi, mode, rng);
}

int bsdf_is_stochastic(const bsdf *b) { return b->kind == BSDF_LAYERED; }

int bsdf_clone(bsdf *dst, const bsdf *src) {
  *dst = *src;
  if (src->kind != BSDF_LAYERED) return 1;
  dst->layered.bottom = NULL;
  bsdf *bottom = malloc(sizeof *bottom);
  if (!bottom) return 0;
  if (!bsdf_clone(bottom, src->layered.bottom)) {
    free(bottom);
    return 0;
  }
  dst->layered.bottom = bottom;
  return 1;
}

void bsdf_release(bsdf *b) {
  if (b->kind != BSDF_LAYERED || !b->layered.bottom) return;
  bsdf_release(b->layered.bottom);
  free(b->layered.bottom);
  b->layered.bottom = NULL;
}
