/* The slab random walk's shared steps, for the three estimators of the
 * layered BSDF (layered.c's walk, layered_lobe.c's whole-lobe walk,
 * layered_sample.c's sampler): free flight with Russian roulette, the
 * isotropic scattering at a medium vertex, and the next-event exit sample
 * through the top with its contributions at medium and bottom vertices.
 *
 * Contract: the random numbers are drawn in one fixed order (at each
 * vertex the roulette, then the flight distance, then the phase direction;
 * the exit samples once per walk, before the first flight), which the
 * stored values of tests/brdf and the bake's ground truth pin: changing the
 * order or the arithmetic changes every estimator's results for a seed.
 * Static inline: the steps sit in the innermost loop. */
#ifndef NBRDF_BRDF_LAYERED_WALK_H
#define NBRDF_BRDF_LAYERED_WALK_H

#include "brdf/dielectric.h"
#include "brdf/disk.h"
#include "brdf/bsdf.h"

#define BRDF_SLAB_INV_4PI (1.0 / (4.0 * M_PI)) /* isotropic phase function */

/* Survivors of the roulette carry about this throughput. 0.25 measured best
 * in walks/s ÷ variance over bench/bench_walk.c's three BRDFs (0.1 .. 1). */
#define BRDF_SLAB_RR_THRESHOLD 0.25
/* Past this many vertices every walk also survives with at most this
 * probability, so that walks in lossless media (A = 1 over a white bottom,
 * σT = 1000) still end in finite expected time. Unbiased, unlike a cap. */
#define BRDF_SLAB_RR_LONG_WALK 512
#define BRDF_SLAB_RR_LONG_SURVIVAL 0.99

/* Russian roulette: returns 0 to end the walk, else rescales *beta. `scale`
 * brings beta to the order of the final contribution (η² in radiance mode,
 * where the exit multiplies by η²). */
static inline int brdf_slab_roulette(double *beta, double scale, int vertex, core_rng *rng) {
  double q = *beta * scale / BRDF_SLAB_RR_THRESHOLD;
  if (vertex > BRDF_SLAB_RR_LONG_WALK) q = fmin(q, BRDF_SLAB_RR_LONG_SURVIVAL);
  if (q >= 1.0) return 1;
  if (!(q > 0.0)) return 0;
  if (core_rng_uniform(rng) >= q) return 0;
  *beta /= q;
  return 1;
}

/* A walk inside the slab: throughput, direction of travel and depth. */
typedef struct brdf_slab_walk {
  const brdf_bsdf_layered *l;
  double beta;     /* throughput, in double (bright media underflow in float) */
  vec3 w;          /* direction of travel (z < 0: downwards) */
  double z;        /* depth below the top, 0..1 */
  double rr_scale; /* brdf_slab_roulette's scale */
  int vertex;      /* vertices visited so far (the roulette's long-walk rule) */
  /* l's constants, copied so that they stay in registers across the calls
   * into the interfaces (which the compiler cannot see through) */
  double sigma_t, albedo;
  int scattering; /* the medium scatters (σT > 0 and A > 0) */
  int delta_top;  /* an index-matched top (η = 1): a Dirac pass-through */
} brdf_slab_walk;

/* Where a flight ended. */
typedef enum brdf_slab_event {
  BRDF_SLAB_END,    /* the roulette ended the walk */
  BRDF_SLAB_MEDIUM, /* a vertex inside the medium at depth z: brdf_slab_scatter next */
  BRDF_SLAB_BOTTOM, /* at the bottom (z = 1), travelling down */
  BRDF_SLAB_TOP     /* at the top (z = 0) from inside, travelling up */
} brdf_slab_event;

/* A walk that has just entered through the top with throughput beta along w. */
static inline brdf_slab_walk brdf_slab_walk_start(const brdf_bsdf_layered *l, brdf_bsdf_mode mode,
                                                  double beta, vec3 w) {
  brdf_slab_walk s;
  s.l = l;
  s.beta = beta;
  s.w = w;
  s.z = 0.0;
  s.rr_scale = mode == BSDF_RADIANCE ? l->top.eta * l->top.eta : 1.0;
  s.vertex = 0;
  s.sigma_t = l->sigma_t;
  s.albedo = l->albedo;
  s.scattering = l->sigma_t > 0.0 && l->albedo > 0.0;
  s.delta_top = l->top.eta == 1.0;
  return s;
}

/* Roulette, then flight along w: to a medium vertex, or to a boundary (a
 * pure absorber attenuates beta along the whole crossing). */
static inline brdf_slab_event brdf_slab_flight(brdf_slab_walk *s, core_rng *rng) {
  if (!brdf_slab_roulette(&s->beta, s->rr_scale, s->vertex++, rng)) return BRDF_SLAB_END;
  const double sigma_t = s->sigma_t;
  if (s->scattering) {
    /* Free flight: optical distance ~ Exp(1), depth changes by t |cos θ|. */
    double t = -log(1.0 - core_rng_uniform(rng)) / sigma_t;
    double zn = s->z - t * s->w.z;
    if (zn > 0.0 && zn < 1.0) {
      s->z = zn;
      return BRDF_SLAB_MEDIUM;
    }
    s->z = zn <= 0.0 ? 0.0 : 1.0;
  } else {
    if (sigma_t > 0.0) s->beta *= exp(-sigma_t / fabs(s->w.z)); /* pure absorber */
    s->z = s->w.z < 0.0 ? 1.0 : 0.0;
  }
  return s->z == 1.0 ? BRDF_SLAB_BOTTOM : BRDF_SLAB_TOP;
}

/* At a medium vertex: albedo, and a new direction from the isotropic phase
 * function, sampled exactly (p / pdf = 1). */
static inline void brdf_slab_scatter(brdf_slab_walk *s, core_rng *rng) {
  s->beta *= s->albedo;
  double x, y, r2;
  brdf_disk_sample(rng, &x, &y, &r2);
  s->w = brdf_disk_to_sphere(x, y, r2);
}

/* Continues the walk along a sampled direction. */
static inline void brdf_slab_bounce(brdf_slab_walk *s, const brdf_bsdf_sample *bs) {
  s->beta *= bs->weight;
  s->w = bs->wi;
}

/* The exit sample for next-event estimation towards one outside direction,
 * drawn once per walk: an inner direction ws drawn from the outside
 * direction in the adjoint mode, so that ratio = f_adj(out, ws) / pdf is the
 * transmission out towards it. Light reaches the exit travelling along
 * up = −ws. */
typedef struct brdf_slab_exit {
  vec3 up;           /* travel direction from a vertex to the exit: −ws */
  double pdf;        /* density of ws (0: no exit sample) */
  double ratio;      /* f / pdf of the exit sample (no cosine; Dirac: 1 / |cos|) */
  double cos;        /* |cos θ| of ws */
  double tr_slab;    /* transmittance of the whole slab along ws */
  double nee_medium; /* A/4π · ratio · MIS weight against the phase function */
} brdf_slab_exit;

/* Draws the exit sample towards `out` (an outside direction, z > 0) for a
 * walk in `mode`; returns 0 (e->pdf = 0) when there is none. */
static inline int brdf_slab_exit_draw(brdf_slab_exit *e, const brdf_bsdf_layered *l, vec3 out,
                                      brdf_bsdf_mode mode, core_rng *rng) {
  brdf_bsdf_sample s;
  if (!brdf_bsdf_dielectric_sample_rng(&l->top, out, brdf_bsdf_adjoint(mode), BSDF_TRANSMISSION,
                                       rng, &s)) {
    e->pdf = 0.0;
    return 0;
  }
  const int delta_top = l->top.eta == 1.0;
  e->up = v3_neg(s.wi);
  e->pdf = s.pdf;
  e->ratio = s.f / s.pdf;
  e->cos = fabs(s.wi.z);
  e->tr_slab = l->sigma_t > 0.0 ? exp(-l->sigma_t / e->cos) : 1.0;
  /* At a medium vertex the partner strategy is the phase function's 1/4π. */
  e->nee_medium = l->albedo * BRDF_SLAB_INV_4PI * e->ratio *
                  (delta_top ? 1.0 : brdf_bsdf_mis_power(s.pdf, BRDF_SLAB_INV_4PI));
  return 1;
}

/* Next-event estimation through the exit at the walk's medium vertex (before
 * brdf_slab_scatter): its contribution. */
static inline double brdf_slab_exit_medium(const brdf_slab_exit *e, const brdf_slab_walk *s) {
  return s->beta * e->nee_medium * exp(-s->sigma_t * s->z / e->cos);
}

/* Next-event estimation through the exit at the bottom, reached travelling
 * along the walk's w: its contribution, 0 where the bottom reflects nothing
 * towards the exit. Evaluates the bottom BSDF (a layered bottom draws from
 * rng). */
static inline double brdf_slab_exit_bottom(const brdf_slab_exit *e, const brdf_slab_walk *s,
                                           brdf_bsdf_mode mode, core_rng *rng) {
  double pb,
      fb = brdf_bsdf_eval_pdf(s->l->bottom, v3_neg(s->w), e->up, mode, BSDF_REFLECTION, rng, &pb);
  if (!(fb > 0.0)) return 0.0;
  double wt = s->delta_top ? 1.0 : brdf_bsdf_mis_power(e->pdf, pb);
  return s->beta * fb * e->cos * wt * e->tr_slab * e->ratio;
}

/* At the bottom: samples its reflection and continues the walk; returns 0
 * when the walk ends there (absorbed, or below the horizon). */
static inline int brdf_slab_bottom_bounce(brdf_slab_walk *s, brdf_bsdf_mode mode, core_rng *rng,
                                          brdf_bsdf_sample *bs) {
  if (!brdf_bsdf_sample_dir(s->l->bottom, v3_neg(s->w), mode, BSDF_REFLECTION, rng, bs)) return 0;
  if (!(bs->wi.z > 0.0)) return 0;
  brdf_slab_bounce(s, bs);
  return 1;
}

#endif
