/* One band of rows of a bake: gathers the six parameters of every texel and
 * colour channel, validates them (naming the file and texel), collapses
 * identical tuples so each distinct one is evaluated once, runs the base
 * tables, the layering network and the sampler on the distinct tuples, and
 * scatters the latents into texels in the latent layout's logical order. */
#ifndef NBRDF_BAKE_BAKE_BAND_H
#define NBRDF_BAKE_BAKE_BAND_H

#include <stddef.h>

#include "bake/bake_audit.h"
#include "bake/bake_fit.h"
#include "bake/bake_sources.h"
#include "bake/bake_tuple.h"
#include "nbrdf/bake.h"
#include "texture/latent_layout.h"
#include "texture/param_source.h"

/* Distinct tuples remembered across bands with their latent, sigma and w
 * (bake_band.c): painted maps repeat the same few tuples in every band. */
typedef struct bake_cache {
  size_t max;       /* entries at most (0: no cache) */
  size_t count;     /* entries held */
  bake_tuple *keys; /* [max] */
  float *vals;      /* [max * (latent_dim + 2)] */
  size_t *table;    /* open addressing, entry index + 1 (0 = empty) */
  size_t table_cap; /* a power of two >= 2 * max */
} bake_cache;

typedef struct bake_band {
  const nbrdf_model *model;
  texture_param_source **src; /* NBRDF_BAKE_PARAM_COUNT sources */
  texture_latent_layout layout;
  int width;
  nbrdf_roughness roughness;
  nbrdf_range_policy range;
  int quantise_bits;                                            /* 0: off */
  float lo[NBRDF_BAKE_PARAM_COUNT], hi[NBRDF_BAKE_PARAM_COUNT]; /* trained ranges */
  /* The lower ends values are taken down to as given (bake_taken_ranges): lo after init; the
   * fitting levels lower alpha1's and alpha2's, whose latents the correction then carries. */
  float take[NBRDF_BAKE_PARAM_COUNT];
  /* scratch, grown as needed */
  bake_tuple *uniq; /* distinct tuples of the band */
  float *uniq_out;  /* their latent, sigma, w: latent_dim + 2 floats each */
  size_t *slot;     /* per texel channel: index into uniq */
  size_t *hash;     /* open-addressing table of uniq indices + 1 (0 = empty) */
  size_t *missing;  /* distinct tuples of the band not in the cache */
  size_t uniq_cap, slot_cap, hash_cap, missing_cap;
  bake_cache cache;
  /* Optional: called between chunks of a band's work (a few rows of the
   * gather, EVAL_CHUNK tuples of the networks) with the fraction of the
   * band done so far, up to BAKE_BAND_FRACTION; non-zero stops the band
   * with NBRDF_ERR_CANCELLED. */
  int (*tick)(void *user, double fraction);
  /* The same for the energy audit's share of the band (stage "audit"); NULL: tick. */
  int (*audit_tick)(void *user, double fraction);
  void *tick_user;
  /* Optional (accuracy levels): the correction added to every distinct
   * tuple's latent after the layering network; the proxy is then predicted
   * from the corrected latent. NULL: the networks' latents as they are. */
  const bake_correction *correct;
  /* Optional: the model the energy audit decodes with (COMPACT: the
   * student, with audit.compact set); NULL: `model`. */
  const nbrdf_model *audit_model;
  /* Optional (borrowed): the networks on a GPU (model_gpu.h); the band then hands them
   * gpu->batch tuples per call. NULL: the CPU, EVAL_CHUNK tuples per call. */
  const struct model_gpu *gpu;
  /* totals over bands */
  size_t evaluated, reused, clamped[NBRDF_BAKE_PARAM_COUNT];
  /* energy audit of the evaluated tuples (bake_audit.h); set up by the
   * caller after bake_band_init, freed by bake_band_free */
  bake_audit audit;
} bake_band;

/* Sets up `b` (the scratch starts empty); the trained ranges come from the
 * model's base-table grids. `cache_max` distinct tuples are remembered
 * across bands (0: none); the cache is allocated on first use.
 * `quantise_bits` (0: off) as nbrdf_bake_options.quantise_bits. */
void bake_band_init(bake_band *b, const nbrdf_model *model, texture_param_source **src,
                    const texture_latent_layout *layout, int width, nbrdf_roughness roughness,
                    nbrdf_range_policy range, size_t cache_max, int quantise_bits);
/* The fraction of a band's time bake_band_run's ticks reach (the rest is
 * the caller's: writing the band). */
#define BAKE_BAND_FRACTION 0.8

/* Computes rows [y0, y0 + rows) into `texels` (rows * width texels of
 * texture_latent_channel_count floats, logical order). */
nbrdf_status bake_band_run(bake_band *b, int y0, int rows, float *texels, nbrdf_error *err);
void bake_band_free(bake_band *b);

/* Recomputes sigma and w of `n` texels (logical order) from their latents:
 * the proxy of averaged latents, for mip levels >= 1. */
nbrdf_status bake_proxy_from_latents(const nbrdf_model *model, const texture_latent_layout *layout,
                                     float *texels, size_t n, nbrdf_error *err);

#endif
