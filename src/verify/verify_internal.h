/* The pieces of nbrdf_verify (include/nbrdf/verify.h), one file each:
 *   verify.c            the public entry: texture and inputs, the loop over texels
 *   verify_scan.c       every tile read, every latent finite
 *   verify_select.c     which texels, and which level-0 texels of a footprint
 *   verify_reference.c  ground-truth lobe images per distinct parameter tuple
 *   verify_decode.c     the texture's latents decoded into the same images
 *   verify_stats.c      medians, percentiles, the report's memory
 *   verify_json.c       the report as JSON
 *   verify_heatmap.c    the error heat-map PNG
 * Lobe image sets follow src/lobe/lobe.h's pixels: VERIFY_N_THETA images of
 * NBRDF_LOBE_RES² doubles, one colour channel each: METRICS.md's θi 0°, 30°,
 * 60°, 80° and the grazing 85°, 89° (what renders see), image k asked of the decoder
 * with ωi and ωo rotated by verify_phi_deg[k] about the normal, so that
 * azimuths off the plane of ωi = (sin θ, 0, cos θ) are seen too (the
 * isotropic truth is the same image; a decoder need not be). */
#ifndef NBRDF_VERIFY_VERIFY_INTERNAL_H
#define NBRDF_VERIFY_VERIFY_INTERNAL_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include "lobe/lobe.h"
#include "nbrdf/verify.h"
#include "texture/latent_exr.h"

#define VERIFY_N_THETA 6
extern const double verify_theta_deg[VERIFY_N_THETA];
extern const double verify_phi_deg[VERIFY_N_THETA];
#define VERIFY_SET ((size_t)VERIFY_N_THETA * NBRDF_LOBE_RES * NBRDF_LOBE_RES)

/* ---- selection ---- */
typedef struct verify_point {
  int x, y;
} verify_point;

/* The texels of a w × h level to compare: all of them when w·h <= n, else
 * one jittered texel per cell of a gx × gy grid with gx·gy <= n and cells
 * about square (stream `level` of `seed`). *out is malloc'd; returns the
 * count, or 0 when out of memory. */
size_t verify_select(int w, int h, int n, uint64_t seed, int level, verify_point **out);

/* Up to `max` level-0 texels of the footprint [x0, x1) × [y0, y1): all of
 * them, or the centres of a regular grid of cells. `out` holds max points;
 * returns the count (>= 1). */
int verify_footprint(int x0, int x1, int y0, int y1, int max, verify_point *out);

/* ---- ground truth ---- */
/* The ground truth's parameters of one colour channel, ids of
 * nbrdf_bake_param_id; the key of the reference cache. */
typedef struct verify_tuple {
  float p[NBRDF_BAKE_PARAM_COUNT];
} verify_tuple;

typedef struct verify_refs verify_refs;

/* A cache of references; `walks` per image and run, `threads` for the walks. */
verify_refs *verify_refs_create(int walks, uint64_t seed, int threads);
void verify_refs_free(verify_refs *r);
/* Two independent runs (a, b: VERIFY_SET doubles each, owned by the cache)
 * of the whole-lobe estimator for `t`, estimated on first use. Moves values
 * outside the ground truth's range onto it and counts them in *clamped. */
nbrdf_status verify_refs_get(verify_refs *r, const verify_tuple *t, const double **a,
                             const double **b, size_t *clamped, nbrdf_error *err);
size_t verify_refs_count(const verify_refs *r);
/* Cancel inside a reference (each costs 8 lobe images of random walks, up to
 * tens of seconds on a loaded machine): the walks stop once *stop becomes
 * non-zero, and tick (may be NULL) is called between chunks of walks with
 * the lobe image of the reference (0..7) being computed; either makes
 * verify_refs_get fail with NBRDF_ERR_CANCELLED. */
void verify_refs_set_cancel(verify_refs *r, const volatile sig_atomic_t *stop,
                            int (*tick)(void *user, int image), void *user);

/* ---- decoding ---- */
typedef struct verify_decoder verify_decoder;

verify_decoder *verify_decoder_create(const nbrdf_model *model);
void verify_decoder_free(verify_decoder *d);
/* The lobe image set of one latent (latent_dim floats) into `images`
 * (VERIFY_SET doubles). Returns 0 in *finite, and leaves `images` alone,
 * when the latent or the decoded values are not finite (a damaged texture). */
nbrdf_status verify_decode(verify_decoder *d, const float *latent, double *images, int *finite,
                           nbrdf_error *err);
size_t verify_decoder_distinct(const verify_decoder *d);
size_t verify_decoder_queries(const verify_decoder *d);

/* ---- integrity ---- */
typedef struct verify_damage {
  size_t texels;   /* texels (any level) with a non-finite latent */
  int level, x, y; /* the first of them */
} verify_damage;

/* Reads every tile of every level of `r` (a damaged tile fails with the
 * reader's message) and counts texels holding non-finite latents. */
nbrdf_status verify_scan(texture_latent_reader *r, verify_damage *d, nbrdf_error *err);

/* ---- statistics ---- */
/* Summary of the texels of `level` (NBRDF_VERIFY_ALL_LEVELS: all). */
nbrdf_verify_summary verify_summarise(const nbrdf_verify_texel *t, size_t n, int level);
/* The q-quantile (0..1) of n values by linear interpolation between order
 * statistics (sorts `v`); NaN when n = 0. */
double verify_quantile(double *v, size_t n, double q);

#endif
