#include "bake/bake_band.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_range.h"
#include "core/error.h"
#include "model/material.h"
#include "model/model_gpu.h"

/* Distinct tuples go through the networks this many at a time, so scratch
 * memory stays bounded whatever the band holds and cancel and progress are
 * seen between chunks: 2,048 tuples cost about 0.09 CPU-s with the default
 * model's layering network (1.1 M MACs each), 0.5 s of wall time even at a
 * load of 12 on the 2-core build machine, and evaluate as many tuples per
 * CPU-second as chunks of 16,384 (docs/RELIABILITY.md, "Cancel and
 * progress"). */
#define EVAL_CHUNK 2048
/* Tuples per energy-audit call (bake_audit.h): a measured tuple costs 6 x 193 decoder
 * queries, and only tuples no anchor's bound clears are measured. A chunk whose every tuple
 * is measured (an untrained or energy-creating model) is ~74 k queries, ~0.15 s on one
 * core: cancel stays within a second even then; larger chunks spread the picks of a round
 * better, but a chunk of 128 measured whole overran test_bake_cancel's allowance. */
#define AUDIT_CHUNK 64

/* Share of a band's time spent gathering and interning its tuples (for the
 * fraction passed to tick; only smoothness of progress depends on it). */
#define GATHER_FRACTION 0.1

static nbrdf_status tick_stage(bake_band *b, int (*fn)(void *, double), double fraction, int y0,
                               int rows, nbrdf_error *err) {
  if (fn && fn(b->tick_user, fraction))
    return core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled in rows %d to %d", y0,
                     y0 + rows - 1);
  return NBRDF_OK;
}

static nbrdf_status tick(bake_band *b, double fraction, int y0, int rows, nbrdf_error *err) {
  return tick_stage(b, b->tick, fraction, y0, rows, err);
}

void bake_band_init(bake_band *b, const nbrdf_model *model, texture_param_source **src,
                    const texture_latent_layout *layout, int width, nbrdf_roughness roughness,
                    nbrdf_range_policy range, size_t cache_max, int quantise_bits) {
  memset(b, 0, sizeof *b);
  b->cache.max = cache_max;
  b->quantise_bits = quantise_bits;
  b->model = model;
  b->src = src;
  b->layout = *layout;
  b->width = width;
  b->roughness = roughness;
  b->range = range;
  model_material_ranges(model, b->lo, b->hi);
  memcpy(b->take, b->lo, sizeof b->take);
}

void bake_band_free(bake_band *b) {
  free(b->uniq);
  free(b->uniq_out);
  free(b->slot);
  free(b->hash);
  free(b->missing);
  free(b->cache.keys);
  free(b->cache.vals);
  free(b->cache.table);
  bake_audit_free(&b->audit);
  memset(b, 0, sizeof *b);
}

static int grow(void **p, size_t *cap, size_t need, size_t elem) {
  if (need <= *cap) return 1;
  void *q = realloc(*p, need * elem);
  if (!q) return 0;
  *p = q;
  *cap = need;
  return 1;
}

/* Applies the roughness convention to one parameter value, validates it and,
 * under the clamp policy, clamps it (bake_tuple.h, shared with eval). */
static nbrdf_status check_value(bake_band *b, int id, float *v, int x, int y, int c,
                                nbrdf_error *err) {
  const float typed = *v;
  model_material_verdict verdict =
      model_material_prepare(b->take, b->hi, id, b->roughness, b->range, v, NULL);
  if (verdict == MODEL_VALUE_CLAMPED) b->clamped[id]++;
  if (verdict <= MODEL_VALUE_CLAMPED) return NBRDF_OK;
  char at[600];
  bake_source_where(b->src, id, x, y, c, at, sizeof at);
  return model_material_fail(verdict, b->take, b->hi, id, b->roughness, at, typed, err);
}

static uint64_t tuple_hash(const bake_tuple *t) {
  uint64_t h = 1469598103934665603ull; /* FNV-1a over the bytes */
  const unsigned char *p = (const unsigned char *)t->p;
  for (size_t i = 0; i < sizeof t->p; i++)
    h = (h ^ p[i]) * 1099511628211ull;
  return h ^ (h >> 29);
}

/* Index of `t` among the band's distinct tuples, adding it if new. */
static size_t intern(bake_band *b, const bake_tuple *t, size_t *n_uniq) {
  size_t mask = b->hash_cap - 1;
  for (size_t i = (size_t)tuple_hash(t) & mask;; i = (i + 1) & mask) {
    size_t e = b->hash[i];
    if (e == 0) {
      b->uniq[*n_uniq] = *t;
      b->hash[i] = ++*n_uniq;
      return *n_uniq - 1;
    }
    if (!memcmp(b->uniq[e - 1].p, t->p, sizeof t->p)) return e - 1;
  }
}

/* ---- the cross-band cache ----
 * Within a band every distinct tuple is evaluated once; the cache carries
 * them to later bands, where painted maps repeat them. It holds at most
 * `max` tuples: a band whose new tuples do not fit empties it first (the
 * newest bands' tuples are the likeliest to come back), and a band with more
 * new tuples than `max` (all-distinct content) leaves it alone. */

static int cache_ready(bake_cache *c, int D) {
  if (c->keys) return 1;
  size_t cap = 16;
  while (cap < 2 * c->max)
    cap *= 2;
  c->keys = malloc(sizeof *c->keys * c->max);
  c->vals = malloc(sizeof(float) * c->max * (size_t)(D + 2));
  c->table = calloc(cap, sizeof *c->table);
  c->table_cap = cap;
  return c->keys && c->vals && c->table;
}

/* Entry index + 1 of `t`, or 0; *slot receives the table slot to fill. */
static size_t cache_find(const bake_cache *c, const bake_tuple *t, size_t *slot) {
  size_t mask = c->table_cap - 1;
  for (size_t i = (size_t)tuple_hash(t) & mask;; i = (i + 1) & mask) {
    size_t e = c->table[i];
    if (e == 0 || !memcmp(c->keys[e - 1].p, t->p, sizeof t->p)) {
      *slot = i;
      return e;
    }
  }
}

static void cache_put(bake_cache *c, const bake_tuple *t, const float *val, int D) {
  size_t slot;
  if (c->count >= c->max || cache_find(c, t, &slot)) return;
  c->keys[c->count] = *t;
  memcpy(c->vals + c->count * (size_t)(D + 2), val, sizeof(float) * (size_t)(D + 2));
  c->table[slot] = ++c->count;
}

/* Fills b->uniq_out of the band's tuples found in the cache and lists the
 * others in b->missing; returns their count. */
static size_t cache_lookup(bake_band *b, size_t n_uniq) {
  const int D = b->layout.latent_dim;
  size_t n_missing = 0;
  for (size_t u = 0; u < n_uniq; u++) {
    size_t slot, e = b->cache.count ? cache_find(&b->cache, &b->uniq[u], &slot) : 0;
    if (e)
      memcpy(b->uniq_out + u * (size_t)(D + 2), b->cache.vals + (e - 1) * (size_t)(D + 2),
             sizeof(float) * (size_t)(D + 2));
    else
      b->missing[n_missing++] = u;
  }
  return n_missing;
}

static void cache_store(bake_band *b, size_t n_missing) {
  bake_cache *c = &b->cache;
  const int D = b->layout.latent_dim;
  if (n_missing > c->max) return;
  if (c->count + n_missing > c->max) {
    memset(c->table, 0, sizeof *c->table * c->table_cap);
    c->count = 0;
  }
  for (size_t k = 0; k < n_missing; k++) {
    size_t u = b->missing[k];
    cache_put(c, &b->uniq[u], b->uniq_out + u * (size_t)(D + 2), D);
  }
}

/* Latent, sigma, w of the distinct tuples idx[0 .. n). */
static nbrdf_status evaluate(bake_band *b, const size_t *idx, size_t n, nbrdf_error *err) {
  nbrdf_status st = bake_tuples_evaluate_on(b->model, b->gpu, b->uniq, idx, n, b->uniq_out, err);
  if (st != NBRDF_OK || !b->correct) return st;
  const size_t D = (size_t)b->layout.latent_dim;
  bake_correct_latents(b->correct, b->uniq, idx, n, b->uniq_out, D + 2);
  float *lat = malloc(sizeof(float) * n * (D + 2));
  if (!lat) return core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for %zu tuples", n);
  float *sigma = lat + n * D, *w = sigma + n;
  for (size_t k = 0; k < n; k++)
    memcpy(lat + k * D, b->uniq_out + idx[k] * (D + 2), sizeof(float) * D);
  st = nbrdf_model_proxy_params(b->model, n, lat, sigma, w, err);
  for (size_t k = 0; st == NBRDF_OK && k < n; k++) {
    b->uniq_out[idx[k] * (D + 2) + D] = sigma[k];
    b->uniq_out[idx[k] * (D + 2) + D + 1] = w[k];
  }
  free(lat);
  return st;
}

nbrdf_status bake_band_run(bake_band *b, int y0, int rows, float *texels, nbrdf_error *err) {
  const int C = texture_latent_colours(&b->layout), D = b->layout.latent_dim;
  const size_t n = (size_t)rows * b->width * C;
  size_t hcap = 16;
  while (hcap < 2 * n)
    hcap *= 2;
  if (!grow((void **)&b->uniq, &b->uniq_cap, n, sizeof *b->uniq) ||
      !grow((void **)&b->slot, &b->slot_cap, n, sizeof *b->slot) ||
      !grow((void **)&b->hash, &b->hash_cap, hcap, sizeof *b->hash) ||
      !grow((void **)&b->missing, &b->missing_cap, n, sizeof *b->missing) ||
      (b->cache.max && !cache_ready(&b->cache, D)))
    return core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for a band of %zu texels", n);
  b->hash_cap = hcap; /* a power of two; extra capacity from an earlier band is unused */
  memset(b->hash, 0, sizeof *b->hash * hcap);

  texture_param_band band[NBRDF_BAKE_PARAM_COUNT];
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    nbrdf_status st = texture_param_source_read_band(b->src[id], y0, rows, &band[id], err);
    if (st != NBRDF_OK) return st;
  }
  size_t n_uniq = 0;
  for (int j = 0; j < rows; j++) {
    nbrdf_status ts = tick(b, GATHER_FRACTION * j / rows, y0, rows, err);
    if (ts != NBRDF_OK) return ts;
    for (int x = 0; x < b->width; x++)
      for (int c = 0; c < C; c++) {
        bake_tuple t;
        for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
          float v = texture_param_band_at(&band[id], x, j, c);
          nbrdf_status st = check_value(b, id, &v, x, y0 + j, c, err);
          if (st != NBRDF_OK) return st;
          t.p[id] = b->quantise_bits ? bake_quantise(b->lo, b->hi, id, b->quantise_bits, v) : v;
        }
        b->slot[((size_t)j * b->width + x) * C + c] = intern(b, &t, &n_uniq);
      }
  }

  free(b->uniq_out);
  b->uniq_out = malloc(sizeof(float) * n_uniq * (size_t)(D + 2));
  if (!b->uniq_out) return core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory");
  size_t n_missing = n_uniq;
  if (b->cache.max)
    n_missing = cache_lookup(b, n_uniq);
  else
    for (size_t u = 0; u < n_uniq; u++)
      b->missing[u] = u;
  const double eval_share = BAKE_BAND_FRACTION - GATHER_FRACTION;
  size_t band_worst = (size_t)-1; /* the audit's new worst tuple, if in this band */
  /* On a GPU, batches of its chunk (~1e5 tuples, tens of milliseconds): cancel is seen
   * between them. */
  const size_t chunk = b->gpu ? b->gpu->batch : EVAL_CHUNK;
  for (size_t k = 0; k < n_missing; k += chunk) {
    nbrdf_status st =
        tick(b, GATHER_FRACTION + eval_share * (double)k / (double)n_missing, y0, rows, err);
    size_t m = n_missing - k < chunk ? n_missing - k : chunk, worst;
    if (st == NBRDF_OK) st = evaluate(b, b->missing + k, m, err);
    /* The audit costs more per tuple than the networks: smaller chunks, so
     * that cancel is still seen well under a second apart. */
    for (size_t j = 0; st == NBRDF_OK && j < m && b->audit.cap; j += AUDIT_CHUNK) {
      size_t q = m - j < AUDIT_CHUNK ? m - j : AUDIT_CHUNK;
      st = tick_stage(b, b->audit_tick ? b->audit_tick : b->tick,
                      GATHER_FRACTION + eval_share * (double)(k + j) / (double)n_missing, y0,
                      rows, err);
      if (st == NBRDF_OK)
        st =
            bake_audit_tuples(&b->audit, b->audit_model ? b->audit_model : b->model, b->uniq,
                              b->lo, b->hi, b->uniq_out, b->missing + k + j, q, &worst, err);
      if (st == NBRDF_OK && worst != (size_t)-1) band_worst = worst;
    }
    if (st != NBRDF_OK) return st;
  }
  if (b->cache.max) cache_store(b, n_missing);
  b->evaluated += n_missing;
  b->reused += n_uniq - n_missing;

  const int texel_floats = texture_latent_channel_count(&b->layout);
  for (size_t i = 0; i < (size_t)rows * b->width; i++) {
    float *texel = texels + i * texel_floats;
    for (int c = 0; c < C; c++) {
      const float *o = b->uniq_out + b->slot[i * C + c] * (size_t)(D + 2);
      for (int k = 0; k < D; k++)
        texel[texture_latent_index_latent(&b->layout, c, k)] = o[k];
      if (b->layout.proxy) {
        texel[texture_latent_index_sigma(&b->layout, c)] = o[D];
        texel[texture_latent_index_w(&b->layout, c)] = o[D + 1];
      }
    }
  }
  /* The first texel of the audit's new worst tuple, for the warning. */
  for (size_t i = 0; band_worst != (size_t)-1 && i < (size_t)rows * b->width * C; i++)
    if (b->slot[i] == band_worst) {
      size_t texel = i / (size_t)C;
      bake_audit_found(&b->audit, &b->uniq[band_worst], (int)(texel % (size_t)b->width),
                       y0 + (int)(texel / (size_t)b->width), (int)(i % (size_t)C));
      break;
    }
  return NBRDF_OK;
}

nbrdf_status bake_proxy_from_latents(const nbrdf_model *model, const texture_latent_layout *layout,
                                     float *texels, size_t n, nbrdf_error *err) {
  if (!layout->proxy || n == 0) return NBRDF_OK;
  const int C = texture_latent_colours(layout), D = layout->latent_dim;
  const int texel_floats = texture_latent_channel_count(layout);
  size_t m = n * C;
  float *lat = malloc(sizeof(float) * m * (D + 2));
  if (!lat) return core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for a mip row");
  float *sigma = lat + m * D, *w = sigma + m;
  for (size_t i = 0; i < n; i++)
    for (int c = 0; c < C; c++)
      for (int k = 0; k < D; k++)
        lat[(i * C + c) * D + k] =
            texels[i * texel_floats + texture_latent_index_latent(layout, c, k)];
  nbrdf_status st = nbrdf_model_proxy_params(model, m, lat, sigma, w, err);
  if (st == NBRDF_OK)
    for (size_t i = 0; i < n; i++)
      for (int c = 0; c < C; c++) {
        texels[i * texel_floats + texture_latent_index_sigma(layout, c)] = sigma[i * C + c];
        texels[i * texel_floats + texture_latent_index_w(layout, c)] = w[i * C + c];
      }
  free(lat);
  return st;
}
