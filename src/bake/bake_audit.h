/* Bake-time energy audit: the largest decoded directional albedo
 * over θi of the distinct latents a bake evaluates (the polar rule of
 * model/albedo_quad.h, measured where a bound cannot clear them, below), the
 * worst of the bake with its texel and parameters. A latent above BAKE_AUDIT_LIMIT creates energy:
 * a renderer shows it as an over-bright rim or fireflies. */
#ifndef NBRDF_BAKE_BAKE_AUDIT_H
#define NBRDF_BAKE_BAKE_AUDIT_H

#include <stddef.h>

#include "bake/bake_audit_rule.h"
#include "bake/bake_tuple.h"
#include "model/decoder.h"
#include "model/netio.h"
#include "nbrdf/model.h"

#define BAKE_AUDIT_LIMIT 1.01
/* Angles of both quadratures, and the directions of bake_albedo_max's: 6 × 32
 * decoder queries per latent. Its maximum over θi is noisy and biased upwards
 * on sharp lobes (measured on α1 0.01, η 1.1, α2 0.3, R0 0.9, A 0.8, σT 0 with
 * the shipped model, 20 seeds: mean 1.32, up to 2.21, against 1.05 ± 0.01 at
 * 16,384 directions), so a latent whose cheap maximum exceeds
 * BAKE_AUDIT_REFINE_ABOVE is measured again with 6 × 1,024 (mean 1.053, up to
 * 1.13 there). */
#define BAKE_AUDIT_SAMPLES 32
#define BAKE_AUDIT_REFINE_ABOVE 0.9
#define BAKE_AUDIT_REFINE_SAMPLES 1024

/* Maximum over bake_audit_theta_deg of the decoded albedo of n latents
 * [n × D] with their proxy sigma [n] (may be NULL): maxv[n], theta_index[n]
 * (may be NULL), by the audit's measurement before cells (the cheap pass and
 * its refinement): what bench/bench_audit_margin.c compares the audit with.
 * Deterministic. */
nbrdf_status bake_albedo_max(const nbrdf_model *model, size_t n, const float *latents,
                             const float *sigma, double *maxv, int *theta_index, nbrdf_error *err);

/* The bake's audit works in parameter space (docs/BAKE.md, "Energy audit"):
 * every measured tuple (bake_albedo_precise) is an anchor, filed in its cell of
 * a grid of BAKE_AUDIT_GRID steps over each parameter's normalised range
 * (model_material_normalise). A tuple is cleared without being measured when
 * an anchor gives the bound anchor + BAKE_AUDIT_NOISE + bake_audit_reach(tuple,
 * anchor) <=
 * BAKE_AUDIT_LIMIT: the slopes bound how fast the decoded albedo moves per unit
 * of normalised parameter (the bundle's, measured for its weights by `nbrdf bundle
 * audit-slopes`; a bundle without them has every distinct tuple measured) and the
 * noise the quadrature's error (bench/bench_audit_margin.c). The anchors of the
 * tuple's cell and of the cells next to it along one parameter are tried first,
 * then every anchor (a material that varies in several parameters at once has
 * its nearest anchors in diagonal cells). The others are measured in rounds of
 * picks spread so that each is expected to clear those near it, the tuples the
 * slopes favour as anchors (high where rising is steeper than falling) picked
 * first; the last round
 * measures all that are left. So a verdict above the limit is never left to a
 * bound, and the worst value is exact (to the quadrature) whenever it is near
 * or above the limit; below it, it is the largest measured value, within the
 * bound's reach of the true largest. Deterministic: tuples are met in bake
 * order. */
#define BAKE_AUDIT_GRID 8
/* The precise measurement's rule: BAKE_AUDIT_POLAR_RINGS x BAKE_AUDIT_POLAR_PHI
 * (bake_audit_rule.h). */
#define BAKE_AUDIT_NOISE 0.03
/* The audit measures a tuple at the angles of BAKE_AUDIT_SCREEN_MASK (bits
 * into bake_audit_theta_deg: 0, 85 and 89 deg) first, half the queries, and
 * at the other three only where the albedo there does not rise towards grazing
 * (rho(0) <= rho(85) <= rho(89)) or its maximum plus BAKE_AUDIT_THETA_GAP
 * exceeds BAKE_AUDIT_LIMIT. bench/bench_audit_screen.c measured where it
 * rises (5,334 of 6,144 tuples of two draws over the whole range, all of the
 * clearcoat's) the maximum over all six angles at most 0.0010 above the
 * maximum over the three; where it does not, up to 0.037. A tuple measured at
 * the three is an anchor with the value max + BAKE_AUDIT_THETA_GAP, and counts
 * for the worst with its max (the header's value can be up to the gap below
 * the six angles' maximum there, and only below the limit). */
#define BAKE_AUDIT_SCREEN_MASK 0x31
#define BAKE_AUDIT_THETA_GAP 0.01
/* The slopes depend on where: the decoded albedo has a steep ridge where both
 * lobes are sharp (alpha1 ~0.01, alpha2 ~0.05: 1.02 to 0.77 over a step of 0.06
 * in normalised alpha2), and is gentle elsewhere. So they are given per region
 * of BAKE_AUDIT_REGIONS x BAKE_AUDIT_REGIONS bins of normalised (alpha1, alpha2)
 * and per direction: slopes[((bin of alpha1 · BAKE_AUDIT_REGIONS + bin of
 * alpha2) · 6 + parameter) · 2 + (0: u above v, 1: u below v)], the bundle's own
 * (model/audit_slopes.h, measured by bake_audit_slopes.h); a bound between two
 * tuples uses the largest slope of every region between them. */
#define BAKE_AUDIT_REGIONS 8
#define BAKE_AUDIT_DIRS 2
/* How far the albedo can rise from the measured tuple v to u:
 * Σ_i slope_i |u_i - v_i|, slope_i the largest over the regions between them in
 * the direction from v_i to u_i; infinite when slopes is NULL (a bundle without
 * them). */
double bake_audit_reach(const double *slopes, const float *u, const float *v);
/* The largest slope of each parameter over all regions and both directions
 * (infinite without slopes). */
void bake_audit_slope_max(const double *slopes, double *slope);

struct gpu_network;

/* Maximum over bake_audit_theta_deg of the decoded albedo of n latents with
 * the polar rule's 6 x (8 x 24 + 1) nodes each, all n in one batch of decoder
 * passes (`gpu`: the decoder on a GPU, or NULL). Deterministic; sigma (the
 * proxies) is not used. Shared with `nbrdf verify`, whose per-texel figure is
 * thus the audit's (where the bake measured a tuple at the screen's three
 * angles only, at most the measured 0.0010 above it). */
nbrdf_status bake_albedo_precise(const nbrdf_model *model, struct gpu_network *gpu, size_t n,
                                 const float *latents, const float *sigma, double *maxv,
                                 int *theta_index, nbrdf_error *err);

/* The same measurement with any decoder of the model's layout on the CPU (a fit's
 * fine-tuned copy, a compact student with its coordinates): the held-out check's energy
 * guard (bake_energy_check.h). */
nbrdf_status bake_albedo_precise_with(const model_decoder *dec, size_t n, const float *latents,
                                      double *maxv, int *theta_index, nbrdf_error *err);

typedef struct bake_audit_cell bake_audit_cell;
typedef struct bake_audit_anchor bake_audit_anchor;

typedef struct bake_audit {
  size_t cap;      /* tuples audited at most (0: off) */
  size_t audited;  /* tuples audited (measured or cleared by an anchor's bound) */
  size_t measured; /* of those, measured with the decoder */
  size_t finished; /* of those, measured at all six angles (the others at the screen's) */
  size_t skipped;  /* evaluated tuples left unaudited past the cap */
  size_t over;     /* measured tuples above BAKE_AUDIT_LIMIT */
  double seconds;  /* process CPU seconds in bake_audit_tuples */
  double worst;    /* largest measured maximum albedo; < 0 before any */
  int worst_theta; /* index into bake_audit_theta_deg */
  int x, y, c;     /* a texel (and colour channel) of the worst */
  bake_tuple tuple;
  /* COMPACT (bake_compact.h): the evaluated latents are the bundle's; the audit
   * decodes their compact coordinates with the model it is given. */
  const struct bake_compact *compact;
  /* Optional (borrowed): the audited model's decoder on a GPU (model_gpu.h). */
  struct gpu_network *gpu_decoder;
  /* the grid's cells met so far (open addressing), each with its anchors */
  bake_audit_cell *cells;
  size_t cells_cap, cells_used;
  bake_audit_anchor *anchors; /* every measured tuple */
  size_t n_anchors, anchors_cap;
  /* scratch */
  float *lat, *sigma, *u;
  double *maxv, *upper, *guess, *rho;
  int *theta;
  size_t *pick, *pending, *rest;
  unsigned char *q;
  size_t scratch_cap;
} bake_audit;

void bake_audit_init(bake_audit *a, size_t cap);
void bake_audit_free(bake_audit *a);

/* Audits n distinct tuples t[idx[k]] (prepared: inside [lo, hi], the trained
 * range) with outputs out[idx[k] · (D + 2) ..] (latent, sigma, w). *band_worst (index into the
 * tuples' numbering, or (size_t)-1) and *band_value receive the worst of them when it beats the
 * bake's so far; the caller then names its texel (bake_audit_found). */
nbrdf_status bake_audit_tuples(bake_audit *a, const nbrdf_model *model, const bake_tuple *t,
                               const float *lo, const float *hi, const float *out,
                               const size_t *idx, size_t n, size_t *band_worst, nbrdf_error *err);
/* Records the texel (x, y, colour c) and parameters of the new worst. */
void bake_audit_found(bake_audit *a, const bake_tuple *t, int x, int y, int c);

/* The warning text for a bake over the limit (or with unaudited tuples);
 * empty when there is nothing to say. */
void bake_audit_message(const bake_audit *a, int rgb, char *buf, size_t cap);

#endif
