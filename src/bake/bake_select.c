#include "bake/bake_select.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_range.h"
#include "core/error.h"
#include "core/rng.h"
#include "model/material.h"

/* Candidates that farthest-point sampling scans at most: each pick costs one
 * pass over them, so 16,384 candidates x a few hundred picks stay well under
 * a second; a larger pool is thinned by a seeded stride first. */
#define FPS_POOL_MAX 16384

#define SELECT_TAG 0x73656c6563746e62ull /* "bntcelse": the selection's random streams */

static uint64_t tuple_hash(const bake_tuple *t) {
  uint64_t h = 1469598103934665603ull;
  const unsigned char *p = (const unsigned char *)t->p;
  for (size_t i = 0; i < sizeof t->p; i++)
    h = (h ^ p[i]) * 1099511628211ull;
  return core_hash64(h, 0);
}

float bake_tuple_distance2(const bake_tuple *a, const bake_tuple *b, const float *lo,
                           const float *hi) {
  float d2 = 0.0f;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    float d = model_material_normalise(lo, hi, id, a->p[id]) -
              model_material_normalise(lo, hi, id, b->p[id]);
    d2 += d * d;
  }
  return d2;
}

typedef struct tuple_set {
  bake_tuple *keys;
  uint64_t *hashes;
  size_t *table; /* entry + 1, 0 empty; capacity 4 x max */
  size_t count, cap;
  unsigned level; /* kept: hashes whose top `level` bits are zero */
} tuple_set;

static int kept(const tuple_set *s, uint64_t h) { return s->level == 0 || (h >> (64 - s->level)) == 0; }

static void rehash(tuple_set *s) {
  memset(s->table, 0, sizeof *s->table * s->cap);
  size_t n = 0;
  for (size_t e = 0; e < s->count; e++) {
    if (!kept(s, s->hashes[e])) continue;
    s->keys[n] = s->keys[e], s->hashes[n] = s->hashes[e];
    size_t i = (size_t)s->hashes[n] & (s->cap - 1);
    while (s->table[i])
      i = (i + 1) & (s->cap - 1);
    s->table[i] = ++n;
  }
  s->count = n;
}

static void set_add(tuple_set *s, const bake_tuple *t, size_t *distinct) {
  uint64_t h = tuple_hash(t);
  size_t i = (size_t)h & (s->cap - 1);
  for (;; i = (i + 1) & (s->cap - 1)) {
    size_t e = s->table[i];
    if (!e) break;
    if (s->hashes[e - 1] == h && !memcmp(s->keys[e - 1].p, t->p, sizeof t->p)) return;
  }
  /* New to the set (perhaps seen before and thinned away: `distinct` then
   * over-counts by those, which only matters beyond the cap). */
  (*distinct)++;
  if (!kept(s, h)) return;
  s->keys[s->count] = *t, s->hashes[s->count] = h;
  s->table[i] = ++s->count;
  while (s->count >= BAKE_SELECT_MAX_DISTINCT) {
    s->level++;
    rehash(s);
  }
}

/* Adds the distinct tuples of one scene to `set`. */
static nbrdf_status gather_scene(tuple_set *set, const bake_scene *sc,
                                 const bake_gather_settings *s, int name_map, size_t *distinct,
                                 nbrdf_error *err) {
  nbrdf_status st = NBRDF_OK;
  const int band_rows = 64;
  texture_param_source **src = sc->src;
  const float *take = s->take ? s->take : s->lo;
  for (int y0 = 0; st == NBRDF_OK && y0 < sc->height; y0 += band_rows) {
    int rows = sc->height - y0 < band_rows ? sc->height - y0 : band_rows;
    if (s->cancel && *s->cancel) {
      st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled while gathering tuples");
      break;
    }
    texture_param_band band[NBRDF_BAKE_PARAM_COUNT];
    for (int id = 0; st == NBRDF_OK && id < NBRDF_BAKE_PARAM_COUNT; id++)
      st = texture_param_source_read_band(src[id], y0, rows, &band[id], err);
    for (int j = 0; st == NBRDF_OK && j < rows; j++)
      for (int x = 0; st == NBRDF_OK && x < sc->width; x++)
        for (int c = 0; st == NBRDF_OK && c < sc->colours; c++) {
          bake_tuple t;
          for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
            float v = texture_param_band_at(&band[id], x, j, c);
            const float typed = v;
            model_material_verdict verdict =
                model_material_prepare(take, s->hi, id, s->roughness, s->range, &v, NULL);
            if (verdict > MODEL_VALUE_CLAMPED) {
              char at[400];
              int len = snprintf(at, sizeof at, "%s at texel (%d, %d)",
                                 model_material_param_name(id), x, y0 + j);
              /* Among several scenes (tiles), the map says which. */
              texture_param_map *m = name_map ? texture_param_source_get_map(src[id]) : NULL;
              if (m && len > 0 && (size_t)len < sizeof at)
                snprintf(at + len, sizeof at - (size_t)len, " of %s", texture_param_map_path(m));
              st = model_material_fail(verdict, take, s->hi, id, s->roughness, at, typed, err);
              break;
            }
            t.p[id] = s->quantise_bits ? bake_quantise(s->lo, s->hi, id, s->quantise_bits, v) : v;
          }
          if (st == NBRDF_OK) set_add(set, &t, distinct);
        }
  }
  return st;
}

nbrdf_status bake_gather_tuples(const bake_scene *scenes, size_t n_scenes,
                                const bake_gather_settings *s, bake_tuple **out, size_t *n,
                                size_t *distinct, nbrdf_error *err) {
  *out = NULL, *n = 0, *distinct = 0;
  tuple_set set = {0};
  set.cap = 4 * (size_t)BAKE_SELECT_MAX_DISTINCT;
  set.keys = malloc(sizeof *set.keys * BAKE_SELECT_MAX_DISTINCT);
  set.hashes = malloc(sizeof *set.hashes * BAKE_SELECT_MAX_DISTINCT);
  set.table = calloc(set.cap, sizeof *set.table);
  nbrdf_status st = NBRDF_OK;
  if (!set.keys || !set.hashes || !set.table)
    st = core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory gathering distinct tuples");
  for (size_t i = 0; st == NBRDF_OK && i < n_scenes; i++)
    st = gather_scene(&set, &scenes[i], s, n_scenes > 1, distinct, err);
  free(set.hashes);
  free(set.table);
  if (st != NBRDF_OK) {
    free(set.keys);
    return st;
  }
  *out = set.keys;
  *n = set.count;
  return NBRDF_OK;
}

void bake_selection_free(bake_selection *sel) {
  free(sel->fit);
  free(sel->held);
  memset(sel, 0, sizeof *sel);
}

nbrdf_status bake_select(const bake_tuple *cand, size_t n, const float *lo, const float *hi,
                         size_t n_fit, size_t n_held, uint64_t seed, bake_selection *sel,
                         nbrdf_error *err) {
  memset(sel, 0, sizeof *sel);
  if (n_fit > n) n_fit = n;
  core_rng rng;
  core_rng_init(&rng, core_hash64(seed, SELECT_TAG), 0);
  /* The pool: every candidate, or a seeded stride through them. */
  size_t pool_n = n < FPS_POOL_MAX ? n : FPS_POOL_MAX;
  size_t *pool = malloc(sizeof *pool * (pool_n ? pool_n : 1));
  float *dist = malloc(sizeof *dist * (pool_n ? pool_n : 1));
  unsigned char *taken = calloc(n ? n : 1, 1);
  sel->fit = malloc(sizeof *sel->fit * (n_fit ? n_fit : 1));
  sel->held = malloc(sizeof *sel->held * (n_held ? n_held : 1));
  if (!pool || !dist || !taken || !sel->fit || !sel->held) {
    free(pool), free(dist), free(taken);
    bake_selection_free(sel);
    return core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory selecting tuples");
  }
  double stride = (double)n / (double)(pool_n ? pool_n : 1);
  double offset = core_rng_uniform(&rng) * stride;
  for (size_t k = 0; k < pool_n; k++) {
    size_t i = (size_t)(offset + stride * (double)k);
    pool[k] = i < n ? i : n - 1;
  }
  /* Farthest-point sampling: the first pick is seeded, each next one is the
   * pool member farthest from every pick so far (ties: the lowest index). */
  for (size_t k = 0; k < pool_n; k++)
    dist[k] = 1e30f;
  size_t next = pool_n ? (size_t)(core_rng_uniform(&rng) * (double)pool_n) : 0;
  if (next >= pool_n) next = pool_n ? pool_n - 1 : 0;
  for (size_t f = 0; f < n_fit && f < pool_n; f++) {
    const bake_tuple *t = &cand[pool[next]];
    sel->fit[sel->n_fit++] = *t;
    taken[pool[next]] = 1;
    size_t best = 0;
    float best_d = -1.0f;
    for (size_t k = 0; k < pool_n; k++) {
      float d = bake_tuple_distance2(t, &cand[pool[k]], lo, hi);
      if (d < dist[k]) dist[k] = d;
      if (!taken[pool[k]] && dist[k] > best_d) best_d = dist[k], best = k;
    }
    if (best_d < 0.0f) break; /* the pool is exhausted */
    next = best;
  }
  size_t untaken = n - sel->n_fit;
  if (untaken == 0) {
    /* Every distinct tuple is fitted: hold out the first picks again, with
     * independent ground truth. */
    sel->held_are_fitted = 1;
    for (size_t k = 0; k < n_held && k < sel->n_fit; k++)
      sel->held[sel->n_held++] = sel->fit[k];
  } else {
    /* Uniform picks among the tuples not fitted (each distinct tuple once,
     * so the estimate weighs the scene's variety, not its texel counts). */
    for (size_t k = 0; k < n_held && sel->n_held < untaken; k++) {
      size_t i = (size_t)(core_rng_uniform(&rng) * (double)n);
      if (i >= n) i = n - 1;
      while (taken[i])
        i = (i + 1) % n;
      taken[i] = 1;
      sel->held[sel->n_held++] = cand[i];
    }
  }
  free(pool), free(dist), free(taken);
  return NBRDF_OK;
}
