/* The internal BSDF interface of the ground truth: evaluate, sample, pdf, with
 * a transport mode, for directions on both sides of an interface. Every BSDF
 * of the library sits behind it, so the layered random walk nests any of
 * them — a layered BSDF included (three layers = a layered BSDF whose bottom
 * is a layered BSDF).
 *
 * Dispatch is a switch on the kind, as pbrt-v4 dispatches its BxDFs through a
 * tagged pointer: the set of BSDFs is closed and small, a BSDF is a plain
 * value that can be copied and nested without a heap of function pointers,
 * and the hot analytic calls stay direct.
 *
 * Conventions (pbrt-v4): local frame z-up; wo and wi both point away from the
 * surface; f(wo, wi) has no cosine factor. `wo` is the direction the path came
 * from (towards the sensor when tracing radiance), `wi` the one sampled next.
 * Radiance mode scales transmission by 1/η'² (η' = η on wi's side over η on
 * wo's side: radiance/η² is invariant across a refraction); importance mode
 * (the adjoint) does not, so f_importance(wo, wi) = f_radiance(wi, wo).
 *
 * Stochastic BSDFs (layered). brdf_bsdf_eval returns an unbiased estimate of f
 * (one random walk) and brdf_bsdf_sample an unbiased weight: E[weight · g(wi)] =
 * ∫ f(wo, wi) |cos θi| g(wi) dwi for any g. Their "pdf" — brdf_bsdf_pdf, and the
 * pdf field of a sample — is a deterministic approximation p̃ of the density
 * of the directions the sampler returns, meant ONLY for multiple importance
 * sampling weights. That is sound: a MIS estimator stays unbiased for any
 * weights w_a(x) + w_b(x) = 1 at every x, and the power heuristic computed
 * with the same deterministic functions (p̃ for this BSDF, the exact pdf for
 * the other strategy) in both strategies' weights sums to one whatever p̃ is.
 * A poor p̃ costs variance, never bias. Never divide by p̃: the sampler's
 * weight already is the f |cos| / p ratio. */
#ifndef NBRDF_BRDF_BSDF_H
#define NBRDF_BRDF_BSDF_H

#include "core/rng.h"
#include "core/vec3.h"

typedef enum brdf_bsdf_mode { BSDF_RADIANCE = 0, BSDF_IMPORTANCE = 1 } brdf_bsdf_mode;

static inline brdf_bsdf_mode brdf_bsdf_adjoint(brdf_bsdf_mode mode) {
  return mode == BSDF_RADIANCE ? BSDF_IMPORTANCE : BSDF_RADIANCE;
}

/* Lobe flags: which lobes a sample/pdf call may use, and what a sample was. */
enum {
  BSDF_REFLECTION = 1,
  BSDF_TRANSMISSION = 2,
  BSDF_ALL = 3,
  BSDF_DELTA = 4 /* sample flag: a Dirac lobe (f and pdf are its weights) */
};

typedef struct brdf_bsdf_sample {
  vec3 wi;       /* the sampled direction, unit, away from the surface */
  double f;      /* f(wo, wi) (an estimate for stochastic BSDFs) */
  double pdf;    /* density of wi (solid angle); p̃ for stochastic BSDFs */
  double weight; /* f |cos θi| / pdf (unbiased estimate for stochastic BSDFs) */
  int flags;     /* BSDF_REFLECTION or BSDF_TRANSMISSION, maybe | BSDF_DELTA */
} brdf_bsdf_sample;

typedef enum brdf_bsdf_kind { BSDF_CONDUCTOR, BSDF_DIELECTRIC, BSDF_LAYERED } brdf_bsdf_kind;

typedef struct brdf_bsdf brdf_bsdf;

/* GGX rough conductor with Schlick Fresnel; reflects on its upper side only. */
typedef struct brdf_bsdf_conductor {
  double alpha, r0;
} brdf_bsdf_conductor;

/* GGX rough dielectric interface (Walter et al. 2007). The upper side is the
 * outside; eta = η_inside / η_outside ≥ 1. eta == 1 is an index-matched,
 * invisible interface: a Dirac pass-through whatever α. */
typedef struct brdf_bsdf_dielectric {
  double alpha, eta;
} brdf_bsdf_dielectric;

/* Paper Fig. 9: dielectric top over a slab of unit thickness (optical depth
 * sigma_t, single-scattering albedo, isotropic phase) over any bottom BSDF,
 * which is owned by the layered BSDF. Reflects on its upper side only. */
typedef struct brdf_bsdf_layered {
  brdf_bsdf_dielectric top;
  double albedo, sigma_t;
  brdf_bsdf *bottom;
} brdf_bsdf_layered;

struct brdf_bsdf {
  brdf_bsdf_kind kind;
  union {
    brdf_bsdf_conductor conductor;
    brdf_bsdf_dielectric dielectric;
    brdf_bsdf_layered layered;
  };
};

double brdf_bsdf_eval(const brdf_bsdf *b, vec3 wo, vec3 wi, brdf_bsdf_mode mode, core_rng *rng);
/* Draws wi given wo among the lobes in `flags`; returns 0 when the draw has no
 * valid direction (absorbed, below the horizon, total internal reflection
 * under BSDF_TRANSMISSION only). */
int brdf_bsdf_sample_dir(const brdf_bsdf *b, vec3 wo, brdf_bsdf_mode mode, int flags, core_rng *rng,
                         brdf_bsdf_sample *s);
/* Density with which brdf_bsdf_sample_dir(wo, mode, flags) returns wi (0 for Dirac
 * lobes); p̃ for stochastic BSDFs (see above). */
double brdf_bsdf_pdf(const brdf_bsdf *b, vec3 wo, vec3 wi, brdf_bsdf_mode mode, int flags);
/* brdf_bsdf_eval and brdf_bsdf_pdf at once (shares the half vector and D). */
double brdf_bsdf_eval_pdf(const brdf_bsdf *b, vec3 wo, vec3 wi, brdf_bsdf_mode mode, int flags,
                          core_rng *rng, double *pdf);
int brdf_bsdf_is_stochastic(const brdf_bsdf *b);

/* Deep copy (the layered bottom chain is duplicated) and release of what a
 * brdf_bsdf owns (not the struct itself). brdf_bsdf_clone returns 0 on allocation
 * failure, leaving *dst owning nothing. */
int brdf_bsdf_clone(brdf_bsdf *dst, const brdf_bsdf *src);
void brdf_bsdf_release(brdf_bsdf *b);

/* The power heuristic (β = 2) weight of a strategy with density pa against
 * one with density pb (Veach 1997). */
static inline double brdf_bsdf_mis_power(double pa, double pb) {
  if (!(pa > 0.0)) return 0.0;
  if (!(pb > 0.0)) return 1.0;
  /* Ratios rather than squares, so that very peaked pdfs cannot overflow. */
  if (pa >= pb) {
    double r = pb / pa;
    return 1.0 / (1.0 + r * r);
  }
  double r = pa / pb;
  return r * r / (1.0 + r * r);
}

#endif
