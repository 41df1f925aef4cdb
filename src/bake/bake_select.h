/* The representative tuples of a scene for the accuracy levels
 * (nbrdf_bake_options.accuracy): the maps' distinct parameter tuples are
 * gathered once, then a fit set is picked by farthest-point sampling in the
 * normalised parameter space (model_material_normalise), which covers the scene's
 * corner of the space evenly whatever the texel counts, and a held-out set is
 * drawn at random among the rest for the error estimate. Everything is a pure
 * function of the maps, the options and the seed. */
#ifndef NBRDF_BAKE_BAKE_SELECT_H
#define NBRDF_BAKE_BAKE_SELECT_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include "bake/bake_tuple.h"
#include "texture/param_source.h"

/* Distinct tuples gathered at most; beyond it the gatherer keeps a
 * deterministic hash-chosen subset (half of the hash space, then a quarter,
 * ...), so a 4K map of all-distinct values costs bounded memory. */
#define BAKE_SELECT_MAX_DISTINCT (1u << 18)

/* One image's sources (a tile of a set, or the whole texture). */
typedef struct bake_scene {
  texture_param_source **src;
  int width, height, colours; /* texture size (1 x 1 for constants), 1 or 3 */
} bake_scene;

typedef struct bake_gather_settings {
  const float *lo, *hi; /* trained ranges */
  const float *take;    /* lower ends taken as given (bake_taken_ranges); NULL: lo */
  nbrdf_roughness roughness;
  nbrdf_range_policy range;
  int quantise_bits;
  volatile sig_atomic_t *cancel; /* may be NULL */
} bake_gather_settings;

/* The distinct tuples (prepared as the bake prepares them: bake_tuple.h) of
 * the maps of n_scenes scenes (the tiles of a set), in the order first met,
 * scene after scene; *distinct receives the number before any thinning. A
 * value the bake would refuse fails here, naming the parameter and texel. */
nbrdf_status bake_gather_tuples(const bake_scene *scenes, size_t n_scenes,
                                const bake_gather_settings *s, bake_tuple **out, size_t *n,
                                size_t *distinct, nbrdf_error *err);

typedef struct bake_selection {
  bake_tuple *fit;  /* [n_fit] */
  bake_tuple *held; /* [n_held] */
  size_t n_fit, n_held;
  /* 1: every distinct tuple is fitted, so the held-out set repeats fitted
   * tuples with independent ground truth (other directions and walks). */
  int held_are_fitted;
} bake_selection;

/* Picks at most n_fit tuples to fit and n_held to hold out among the n
 * candidates. Fails only when out of memory. */
nbrdf_status bake_select(const bake_tuple *cand, size_t n, const float *lo, const float *hi,
                         size_t n_fit, size_t n_held, uint64_t seed, bake_selection *sel,
                         nbrdf_error *err);
void bake_selection_free(bake_selection *sel);

/* Squared distance of two tuples in the normalised parameter space. */
float bake_tuple_distance2(const bake_tuple *a, const bake_tuple *b, const float *lo,
                           const float *hi);

#endif
