#include "train/params.h"

#include <math.h>
#include <string.h>

#include "core/rng.h"
#include "model/material.h"

/* Domain tags of the two seed families (arbitrary, different, never change:
 * changing one silently changes every data set and held-out set). */
#define TRAIN_TAG UINT64_C(0x6e62726466747261)   /* "nbrdftra" */
#define HELDOUT_TAG UINT64_C(0x6e62726466686f6c) /* "nbrdfhol" */

static const char *const KIND_NAMES[] = {"conductor", "dielectric", "layered2", "layered3",
                                         "single"};

const char *train_kind_name(train_kind kind) {
  return (unsigned)kind < 5u ? KIND_NAMES[kind] : "unknown";
}

int train_kind_parse(const char *name) {
  for (int k = 0; k < 5; k++)
    if (name && strcmp(name, KIND_NAMES[k]) == 0) return k;
  return -1;
}

uint64_t train_family_seed(uint64_t seed) { return core_hash64(TRAIN_TAG, seed); }

uint64_t train_heldout_seed(train_heldout set) { return core_hash64(HELDOUT_TAG, (uint64_t)set); }

train_kind train_heldout_kind(train_heldout set) {
  switch (set) {
  case TRAIN_HELDOUT_LAYER3:
    return TRAIN_LAYERED3;
  case TRAIN_HELDOUT_SINGLE:
    return TRAIN_SINGLE;
  default:
    return TRAIN_LAYERED2;
  }
}

/* α = U(0.216, 1)^3: cube of a uniform, so roughness is spread evenly in
 * perceptual terms (0.216^3 ≈ 0.01). */
double train_draw_alpha(double u) {
  double t = 0.216 + (1.0 - 0.216) * u;
  return t * t * t;
}
double train_draw_eta(double u) { return 1.05 + (2.0 - 1.05) * u; }
double train_draw_albedo(double u) { return 1.0 - u * u; }
double train_draw_sigma_t(double u) {
  static const double SIGMA_T[4] = {0.0, 1.0, 2.0, NBRDF_BAKE_SIGMA_T_MAX};
  int i = (int)(u * 4.0);
  return SIGMA_T[i < 0 ? 0 : i > 3 ? 3 : i];
}

static const char *const DRAWS_NAMES[] = {"table2", "coverage", "tails", "mirror"};
#define N_DRAWS ((int)(sizeof DRAWS_NAMES / sizeof *DRAWS_NAMES))

const char *train_draws_name(train_draws draws) {
  return (unsigned)draws < (unsigned)N_DRAWS ? DRAWS_NAMES[draws] : "?";
}

int train_draws_parse(const char *name) {
  for (int d = 0; d < N_DRAWS; d++)
    if (name && !strcmp(name, DRAWS_NAMES[d])) return d;
  return -1;
}

int train_tails_region(uint64_t index) { return (int)(index % TRAIN_TAILS_REGIONS); }

const char *train_tails_region_name(int region) {
  static const char *const names[TRAIN_TAILS_REGIONS] = {"eta<=1.2", "alpha1<=0.05", "both"};
  return (unsigned)region < TRAIN_TAILS_REGIONS ? names[region] : "?";
}

/* 15 %: log-uniform on [0.01, 0.03]; 85 %: Table 2's cube law restricted to
 * (0.03, 1] (its own share there is 88 %, so the rest keeps its shape). */
double train_draw_alpha_coverage(double u) {
  if (u < 0.15) return 0.01 * pow(3.0, u / 0.15);
  double lo = cbrt(0.03), t = lo + (1.0 - lo) * (u - 0.15) / 0.85;
  return t * t * t;
}

/* 5 %: η = 1 (no coat); 15 %: U(1, 1.2); 80 %: U(1.2, 2). */
double train_draw_eta_coverage(double u) {
  if (u < 0.05) return 1.0;
  if (u < 0.20) return 1.0 + 0.2 * (u - 0.05) / 0.15;
  return 1.2 + 0.8 * (u - 0.20) / 0.80;
}

/* TAILS: region 0 low IOR, 1 sharp, 2 both (train_tails_region). */
static double draw_alpha_tails(int region, double u) {
  if (region == 0) {
    double lo = cbrt(0.05), t = lo + (1.0 - lo) * u;
    return t * t * t;
  }
  return 0.01 * pow(5.0, u);
}
static double draw_eta_tails(int region, double u) {
  return region == 1 ? 1.2 + 0.8 * u : 1.0 + 0.2 * u;
}

/* MIRROR's coat α: log-uniform on [0.01, 0.05] half the time (one uniform, split). */
static double draw_alpha_mirror(double u) {
  return u < 0.5 ? 0.01 * pow(5.0, 2.0 * u) : train_draw_alpha(2.0 * u - 1.0);
}

/* `region` matters to TAILS only. */
static double draw_alpha(train_draws d, int region, double u) {
  return d == TRAIN_DRAWS_COVERAGE ? train_draw_alpha_coverage(u)
         : d == TRAIN_DRAWS_TAILS  ? draw_alpha_tails(region, u)
         : d == TRAIN_DRAWS_MIRROR ? draw_alpha_mirror(u)
                                   : train_draw_alpha(u);
}
static double draw_eta(train_draws d, int region, double u) {
  return d == TRAIN_DRAWS_COVERAGE || d == TRAIN_DRAWS_MIRROR ? train_draw_eta_coverage(u)
         : d == TRAIN_DRAWS_TAILS                             ? draw_eta_tails(region, u)
                                                              : train_draw_eta(u);
}

static void draw_coat(core_rng *rng, train_draws d, int region, train_coat *c) {
  c->alpha = draw_alpha(d, region, core_rng_uniform(rng));
  c->eta = draw_eta(d, region, core_rng_uniform(rng));
  c->albedo = train_draw_albedo(core_rng_uniform(rng));
  c->sigma_t = train_draw_sigma_t(core_rng_uniform(rng));
}

void train_params_draw(uint64_t family, train_kind kind, uint64_t index, train_params *p) {
  train_params_draw_from(family, kind, TRAIN_DRAWS_TABLE2, index, p);
}

void train_params_draw_from(uint64_t family, train_kind kind, train_draws draws, uint64_t index,
                            train_params *p) {
  /* The kind enters the generator seed, so that layered2 and layered3 sets
   * drawn with the same seed do not share their outer coats. */
  core_rng rng;
  core_rng_init(&rng, core_hash64(family, (uint64_t)kind), index);
  memset(p, 0, sizeof *p);
  if (kind == TRAIN_SINGLE)
    kind = core_rng_uniform(&rng) < 0.5 ? TRAIN_CONDUCTOR : TRAIN_DIELECTRIC;
  p->kind = kind;
  p->n_coats = kind == TRAIN_LAYERED2 ? 1 : kind == TRAIN_LAYERED3 ? 2 : 0;
  int region = train_tails_region(index);
  for (int c = 0; c < p->n_coats; c++)
    draw_coat(&rng, draws, region, &p->coat[c]);
  /* The conductor base keeps Table 2's α; a dielectric is a coat on its own. */
  double u = core_rng_uniform(&rng);
  int mirror = draws == TRAIN_DRAWS_MIRROR && kind != TRAIN_DIELECTRIC;
  p->base_alpha = kind == TRAIN_DIELECTRIC ? draw_alpha(draws, region, u)
                  : mirror                 ? 0.01 * pow(5.0, u)
                                           : train_draw_alpha(u);
  if (kind == TRAIN_DIELECTRIC)
    p->base_eta = draw_eta(draws, region, core_rng_uniform(&rng));
  else
    p->base_r0 = mirror ? 1.0 - 0.2 * core_rng_uniform(&rng) : core_rng_uniform(&rng);
}

nbrdf_status train_params_create(const train_params *p, nbrdf_brdf **out, nbrdf_error *err) {
  if (p->kind == TRAIN_LAYERED2) { /* the layered material, built in one place */
    const train_coat *k = &p->coat[0];
    double m[MODEL_MATERIAL_PARAMS];
    m[NBRDF_BAKE_ALPHA1] = k->alpha, m[NBRDF_BAKE_ETA] = k->eta;
    m[NBRDF_BAKE_ALPHA2] = p->base_alpha, m[NBRDF_BAKE_R0] = p->base_r0;
    m[NBRDF_BAKE_ALBEDO] = k->albedo, m[NBRDF_BAKE_SIGMA_T] = k->sigma_t;
    return model_material_truth(m, out, err);
  }
  nbrdf_brdf *b = NULL;
  nbrdf_status st = p->kind == TRAIN_DIELECTRIC
                        ? nbrdf_brdf_create_dielectric(p->base_alpha, p->base_eta, &b, err)
                        : nbrdf_brdf_create_conductor(p->base_alpha, p->base_r0, &b, err);
  /* Innermost coat first: coat[n_coats - 1] sits on the base. */
  for (int c = p->n_coats - 1; c >= 0 && st == NBRDF_OK; c--) {
    const train_coat *k = &p->coat[c];
    nbrdf_brdf *layered = NULL;
    st = nbrdf_brdf_create_layered(k->alpha, k->eta, k->albedo, k->sigma_t, b, &layered, err);
    nbrdf_brdf_destroy(b);
    b = layered;
  }
  if (st != NBRDF_OK) {
    nbrdf_brdf_destroy(b);
    return st;
  }
  *out = b;
  return NBRDF_OK;
}
