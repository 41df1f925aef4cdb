/* BRDF parameters for training and held-out evaluation, drawn from the
 * paper's Table 2 distributions (Fan et al. 2022; DESIGN.md):
 *   α = U(0.216, 1)^3 (0.01..1), η ∈ U(1.05, 2), R0 ∈ U(0, 1),
 *   A = 1 − U(0, 1)^2, σT uniform in {0, 1, 2, 5}.
 *
 * Every draw is a pure function of (family seed, index): BRDF k uses PCG32
 * stream k of the family seed, so sets can be generated in any order, by any
 * number of threads, and resumed.
 *
 * Training and held-out sets are kept disjoint by construction: the family
 * seed of a training set is core_hash64(TRAIN_TAG, user seed), that of a
 * held-out set core_hash64(HELDOUT_TAG, set id), with two different tags;
 * the generators of the two families therefore start from different states
 * (a collision would need a splitmix64 collision between the two inputs), and
 * the parameters are continuous, so no held-out BRDF reappears in training
 * data whatever seed the user picks. */
#ifndef NBRDF_TRAIN_PARAMS_H
#define NBRDF_TRAIN_PARAMS_H

#include <stdint.h>

#include "nbrdf/brdf.h"

typedef enum train_kind {
  TRAIN_CONDUCTOR = 0,  /* rough conductor (α, R0) */
  TRAIN_DIELECTRIC = 1, /* rough dielectric interface (α, η), reflection only */
  TRAIN_LAYERED2 = 2,   /* dielectric coat over a slab over a conductor */
  TRAIN_LAYERED3 = 3,   /* coat + slab over (coat + slab over a conductor) */
  TRAIN_SINGLE = 4      /* draw only: conductor or dielectric, half each */
} train_kind;

/* One coat of a layered BRDF: dielectric top (alpha, eta) over a unit slab. */
typedef struct train_coat {
  double alpha, eta, albedo, sigma_t;
} train_coat;

/* A drawn BRDF. coat[0] is the outermost; coats beyond n_coats are zero.
 * The base is a conductor (base_alpha, base_r0) for every kind but
 * TRAIN_DIELECTRIC, whose interface is (base_alpha, base_eta). */
typedef struct train_params {
  train_kind kind; /* never TRAIN_SINGLE after a draw */
  int n_coats;     /* 0, 1 or 2 */
  train_coat coat[2];
  double base_alpha, base_r0, base_eta;
} train_params;

/* Parameter distributions of a training set. Held-out sets always
 * draw TABLE2, so figures stay comparable across models.
 * - TABLE2: the paper's Table 2 (above).
 * - COVERAGE: Table 2 with more of what the shipped model got worst: coat
 *   (and dielectric) η = 1 exactly (no coat) 5 %, η ∈ U(1, 1.2) 15 % (so 20 %
 *   in [1, 1.2]), U(1.2, 2) 80 %; coat (and dielectric) α ≤ 0.03 15 %
 *   (log-uniform on [0.01, 0.03]), otherwise Table 2's cube law above 0.03.
 *   The conductor base, A and σT are Table 2's. One uniform per parameter in
 *   the same order, so the two differ only in the warps. */
/* - TAILS: only the regions where the universal path is weakest, a third each by
 *   index % 3: low-IOR coats (η ∈ U(1, 1.2), α > 0.05 by Table 2's cube law), sharp coats
 *   (α log-uniform on [0.01, 0.05], η ∈ U(1.2, 2)), and both (η ∈ U(1, 1.2), α
 *   log-uniform on [0.01, 0.05]). The base, A and σT are Table 2's. The `tails` held-out
 *   set draws these, so its figures are per region. */
typedef enum train_draws {
  TRAIN_DRAWS_TABLE2 = 0,
  TRAIN_DRAWS_COVERAGE = 1,
  TRAIN_DRAWS_TAILS = 2,
  /* - MIRROR: the corner of smooth, bright bases, where a coat must keep almost all the
   *   light (the `extremes` set's smooth coat over a mirror): conductor α log-uniform on
   *   [0.01, 0.05], R0 ∈ U(0.8, 1); coats with COVERAGE's η (η = 1 included) and α
   *   log-uniform on [0.01, 0.05] half the time, Table 2's otherwise; A and σT Table 2's. */
  TRAIN_DRAWS_MIRROR = 3
} train_draws;
/* The TAILS region of draw `index`: 0 low IOR, 1 sharp, 2 both. */
#define TRAIN_TAILS_REGIONS 3
int train_tails_region(uint64_t index);
const char *train_tails_region_name(int region);
const char *train_draws_name(train_draws draws);
/* "table2" / "coverage" / "tails"; -1 if none. */
int train_draws_parse(const char *name);

/* The held-out sets of docs/METRICS.md. */
typedef enum train_heldout {
  TRAIN_HELDOUT_REP = 1,    /* two-layer BRDFs (projected) */
  TRAIN_HELDOUT_LAYER = 2,  /* two-layer BRDFs (end to end) */
  TRAIN_HELDOUT_LAYER3 = 3, /* three-layer BRDFs */
  TRAIN_HELDOUT_SINGLE = 4, /* conductors and dielectrics */
  TRAIN_HELDOUT_TAILS = 5   /* two-layer BRDFs, TRAIN_DRAWS_TAILS */
} train_heldout;

const char *train_kind_name(train_kind kind);
/* Parses "conductor", "dielectric", "layered2", "layered3", "single"; -1 if none. */
int train_kind_parse(const char *name);

/* The family seed of a training set drawn with the user's seed. */
uint64_t train_family_seed(uint64_t seed);
/* The fixed family seed of a held-out set (never equal to a training one). */
uint64_t train_heldout_seed(train_heldout set);
/* The kind a held-out set draws. */
train_kind train_heldout_kind(train_heldout set);

/* BRDF `index` of the family: p is a pure function of (family, kind, index);
 * it uses stream `index` of the seed core_hash64(family, kind). */
void train_params_draw(uint64_t family, train_kind kind, uint64_t index, train_params *p);
/* The same from the distribution `draws` (TABLE2: train_params_draw). */
void train_params_draw_from(uint64_t family, train_kind kind, train_draws draws, uint64_t index,
                            train_params *p);

/* The ground-truth BRDF of p. */
nbrdf_status train_params_create(const train_params *p, nbrdf_brdf **out, nbrdf_error *err);

/* Table 2 draws from uniforms u ∈ [0, 1) (exposed for tests). */
double train_draw_alpha(double u);
double train_draw_eta(double u);
double train_draw_albedo(double u);
double train_draw_sigma_t(double u);
/* COVERAGE's warps of α (coats, dielectrics) and η. */
double train_draw_alpha_coverage(double u);
double train_draw_eta_coverage(double u);

#endif
