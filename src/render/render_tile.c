/* Shading one tile: camera rays, texel fetch, light and BRDF samples with
 * MIS, then the BRDF values of every query of the batch at once (decoder
 * or ground truth). The scene is one convex object, so direct lighting is
 * the whole light transport (render.h). */
#include "render/render_tile.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/progress.h"
#include "core/rng.h"
#include "render/render_sampling.h"

/* A BRDF value still to be computed: acc[pix] += f(wi, wo)[c] · factor[c]. */
typedef struct query {
  int pix;  /* pixel within the tile */
  int slot; /* pixel sample whose texel it uses */
  float wi[3], wo[3];
  double factor[3]; /* per output channel: radiance · cos θo · MIS weight / pdf */
} query;

typedef struct tile_buf {
  double *acc;
  core_rng *rng;
  float *texel; /* per slot: channels floats */
  query *q;
  float *latent, *wi, *wo, *f; /* decoder batch */
  nbrdf_query *gt;             /* ground-truth batch */
  double *fd;
} tile_buf;

static void buf_free(tile_buf *b) {
  free(b->acc), free(b->rng), free(b->texel), free(b->q);
  free(b->latent), free(b->wi), free(b->wo), free(b->f), free(b->gt), free(b->fd);
}

/* Proxy (sigma, w) of texture colour c; a texture without them samples like Lambert. */
static void texel_proxy(const texture_latent_image *tex, const float *texel, int c, float *s,
                        float *w) {
  if (!tex->layout.proxy) {
    *s = 1.0f, *w = 1.0f;
    return;
  }
  *s = texel[texture_latent_index_sigma(&tex->layout, c)];
  *w = texel[texture_latent_index_w(&tex->layout, c)];
  if (!(*s > 1e-3f)) *s = 1e-3f;
  *w = *w < 0.0f ? 0.0f : (*w > 1.0f ? 1.0f : *w);
}

/* The density the MIS weights give the BRDF strategy of output channel c:
 * the texture's proxy mixture (NEURAL, and REFERENCE with one channel) or
 * channel c's proxy (REFERENCE per channel). */
static double strategy_pdf(const render_ctx *ctx, const float *texel, int c, vec3 wi, vec3 wo) {
  const texture_latent_image *tex = ctx->tex;
  int T = texture_latent_colours(&tex->layout);
  float s[3], w[3];
  for (int k = 0; k < T; k++)
    texel_proxy(tex, texel, k, &s[k], &w[k]);
  if (ctx->opts->mode == NBRDF_RENDER_NEURAL || ctx->colours == 1)
    return render_proxy_mix_pdf(T, s, w, wi, wo);
  int k = c < T ? c : T - 1;
  return render_proxy_mix_pdf(1, &s[k], &w[k], wi, wo);
}

static void set3f(float *d, vec3 v) { d[0] = (float)v.x, d[1] = (float)v.y, d[2] = (float)v.z; }

/* Evaluates every query and adds f · factor to the pixels. */
static nbrdf_status eval_queries(const render_ctx *ctx, tile_buf *b, int nq, const float *tex_buf,
                                 uint64_t seed, size_t *decoded, double *decode_seconds,
                                 size_t *brdf_evals, nbrdf_error *err) {
  if (nq == 0) return NBRDF_OK;
  const texture_latent_image *tex = ctx->tex;
  int K = ctx->colours;
  if (ctx->opts->mode == NBRDF_RENDER_NEURAL) {
    int D = tex->layout.latent_dim, block = texture_latent_block(&tex->layout);
    for (int k = 0; k < nq; k++) {
      const float *texel = tex_buf + (size_t)b->q[k].slot * tex->channels;
      for (int c = 0; c < K; c++)
        memcpy(b->latent + ((size_t)k * K + c) * D, texel + (size_t)c * block, sizeof(float) * D);
      memcpy(b->wi + 3 * k, b->q[k].wi, sizeof(float) * 3);
      memcpy(b->wo + 3 * k, b->q[k].wo, sizeof(float) * 3);
    }
    double t0 = core_monotonic_seconds();
    nbrdf_status st =
        nbrdf_model_decode(ctx->model, (size_t)nq, K, b->latent, b->wi, b->wo, b->f, err);
    if (st != NBRDF_OK) return st;
    *decode_seconds += core_monotonic_seconds() - t0;
    *decoded += (size_t)nq * K;
    for (int k = 0; k < nq; k++)
      for (int o = 0; o < 3; o++)
        b->acc[3 * b->q[k].pix + o] +=
            b->f[(size_t)k * K + (o < K ? o : K - 1)] * b->q[k].factor[o];
    return NBRDF_OK;
  }
  for (int k = 0; k < nq; k++)
    for (int a = 0; a < 3; a++)
      b->gt[k].wi[a] = b->q[k].wi[a], b->gt[k].wo[a] = b->q[k].wo[a];
  for (int c = 0; c < K; c++) {
    nbrdf_eval_options eo = NBRDF_EVAL_OPTIONS_DEFAULT;
    eo.seed = core_hash64(seed, (uint64_t)c), eo.spp = 1, eo.threads = 1;
    nbrdf_status st =
        nbrdf_brdf_eval(ctx->opts->reference[c], (size_t)nq, b->gt, &eo, b->fd, NULL, err);
    if (st != NBRDF_OK) return st;
    *brdf_evals += (size_t)nq;
    for (int k = 0; k < nq; k++)
      for (int o = 0; o < 3; o++)
        if (K == 1 || o == c) b->acc[3 * b->q[k].pix + o] += b->fd[k] * b->q[k].factor[o];
  }
  return NBRDF_OK;
}

/* REFERENCE: one sample of the ground truth's own sampler per channel, its
 * weight (f cos / p, unbiased) times radiance and the MIS weight. */
static nbrdf_status reference_brdf_samples(const render_ctx *ctx, const render_hit *hit,
                                           const float *texel, vec3 wi, uint64_t seed,
                                           uint64_t index, double *acc, size_t *brdf_evals,
                                           nbrdf_error *err) {
  double a[3] = {wi.x, wi.y, wi.z};
  for (int c = 0; c < ctx->colours; c++) {
    double wo[3], weight;
    nbrdf_status st = nbrdf_brdf_sample(ctx->opts->reference[c], a, seed, index * 3 + (uint64_t)c,
                                        wo, &weight, err);
    if (st != NBRDF_OK) return st;
    (*brdf_evals)++;
    if (!(weight > 0.0) || !(wo[2] > 0.0)) continue;
    vec3 lo = v3(wo[0], wo[1], wo[2]), dir = render_to_world(hit, lo);
    if (render_camera_occluded(&ctx->cam, hit, dir, INFINITY)) continue;
    double le[3];
    render_env_radiance(ctx->env, dir, le);
    double mis =
        render_power_heuristic(strategy_pdf(ctx, texel, c, wi, lo), render_env_pdf(ctx->env, dir));
    for (int o = 0; o < 3; o++)
      if (ctx->colours == 1 || o == c) acc[o] += weight * le[o] * mis;
  }
  return NBRDF_OK;
}

static int push(tile_buf *b, int *nq, int pix, int slot, vec3 wi, vec3 wo) {
  query *q = &b->q[(*nq)++];
  q->pix = pix, q->slot = slot;
  set3f(q->wi, wi), set3f(q->wo, wo);
  return *nq - 1;
}

nbrdf_status render_tile(const render_ctx *ctx, int tile, int x0, int y0, int w, int h, float *rgb,
                         size_t *decoded, double *decode_seconds, size_t *brdf_evals,
                         nbrdf_error *err) {
  const nbrdf_render_options *o = ctx->opts;
  const texture_latent_image *tex = ctx->tex;
  int npix = w * h, spp = o->spp, C = tex->channels;
  int per_chunk = RENDER_BATCH / npix > 0 ? RENDER_BATCH / npix : 1;
  if (per_chunk > spp) per_chunk = spp;
  size_t slots = (size_t)npix * per_chunk, maxq = 3 * slots, K = (size_t)ctx->colours;
  int D = tex->layout.latent_dim;
  tile_buf b = {0};
  b.acc = calloc((size_t)npix * 3, sizeof(double));
  b.rng = malloc(sizeof(core_rng) * npix);
  b.texel = malloc(sizeof(float) * slots * C);
  b.q = malloc(sizeof(query) * maxq);
  if (o->mode == NBRDF_RENDER_NEURAL) {
    b.latent = malloc(sizeof(float) * maxq * K * D);
    b.wi = malloc(sizeof(float) * maxq * 3), b.wo = malloc(sizeof(float) * maxq * 3);
    b.f = malloc(sizeof(float) * maxq * K);
  } else {
    b.gt = malloc(sizeof(nbrdf_query) * maxq), b.fd = malloc(sizeof(double) * maxq);
  }
  if (!b.acc || !b.rng || !b.texel || !b.q ||
      (o->mode == NBRDF_RENDER_NEURAL ? !b.latent || !b.wi || !b.wo || !b.f : !b.gt || !b.fd)) {
    buf_free(&b);
    return core_fail(err, NBRDF_ERR_MEMORY, "render: tile %d: out of memory", tile);
  }
  for (int p = 0; p < npix; p++)
    core_rng_init(&b.rng[p], o->seed, (uint64_t)(y0 + p / w) * o->width + (uint64_t)(x0 + p % w));
  nbrdf_status st = NBRDF_OK;
  for (int s0 = 0; st == NBRDF_OK && s0 < spp; s0 += per_chunk) {
    /* a tile of thousands of samples per pixel takes seconds: Ctrl-C is seen
     * between its batches too (the caller reports progress per tile) */
    if (o->cancel && *o->cancel) {
      st = core_fail(err, NBRDF_ERR_CANCELLED, "render: cancelled in tile %d", tile);
      break;
    }
    int s1 = s0 + per_chunk < spp ? s0 + per_chunk : spp, nq = 0;
    for (int p = 0; st == NBRDF_OK && p < npix; p++) {
      int px = x0 + p % w, py = y0 + p / w;
      uint64_t gpix = (uint64_t)py * o->width + (uint64_t)px;
      for (int s = s0; st == NBRDF_OK && s < s1; s++) {
        int slot = p * per_chunk + (s - s0);
        core_rng *r = &b.rng[p];
        double jx = core_rng_uniform(r), jy = core_rng_uniform(r);
        double ue[2] = {core_rng_uniform(r), core_rng_uniform(r)};
        double ub[4];
        for (int k = 0; k < 4; k++)
          ub[k] = core_rng_uniform(r);
        vec3 dir = render_camera_ray(&ctx->cam, px + jx, py + jy);
        render_hit hit;
        if (!render_camera_hit(&ctx->cam, dir, tex->width[0], tex->height[0], &hit)) {
          double le[3];
          render_env_radiance(ctx->env, dir, le);
          for (int k = 0; k < 3; k++)
            b.acc[3 * p + k] += le[k];
          continue;
        }
        vec3 wi = render_to_local(&hit, v3_neg(dir));
        if (!(wi.z > 1e-4)) continue;
        wi = v3_normalize(wi);
        float *texel = b.texel + (size_t)slot * C;
        texture_latent_fetch(tex, (float)hit.u, (float)hit.v, o->mip ? (float)hit.lod : 0.0f,
                             texel);
        /* The point light: a delta light, next-event estimation only. */
        if (o->light_intensity > 0.0) {
          vec3 l = v3_sub(v3(o->light_pos[0], o->light_pos[1], o->light_pos[2]), hit.p);
          double d2 = v3_dot(l, l);
          vec3 ld = v3_scale(l, 1.0 / sqrt(d2)), lo = render_to_local(&hit, ld);
          if (lo.z > 1e-4 && !render_camera_occluded(&ctx->cam, &hit, ld, sqrt(d2))) {
            query *q = &b.q[push(&b, &nq, p, slot, wi, v3_normalize(lo))];
            for (int k = 0; k < 3; k++)
              q->factor[k] = o->light_intensity / d2 * lo.z;
          }
        }
        /* One environment sample, MIS-weighted against the BRDF strategy. */
        vec3 ed;
        double pl = render_env_sample(ctx->env, ue[0], ue[1], &ed);
        vec3 lo = render_to_local(&hit, ed);
        if (pl > 0.0 && lo.z > 1e-4 && !render_camera_occluded(&ctx->cam, &hit, ed, INFINITY)) {
          lo = v3_normalize(lo);
          double le[3];
          render_env_radiance(ctx->env, ed, le);
          query *q = &b.q[push(&b, &nq, p, slot, wi, lo)];
          for (int k = 0; k < 3; k++) {
            int c = (int)K == 1 ? 0 : k;
            q->factor[k] =
                le[k] * lo.z * render_power_heuristic(pl, strategy_pdf(ctx, texel, c, wi, lo)) / pl;
          }
        }
        /* One BRDF sample. */
        if (o->mode == NBRDF_RENDER_REFERENCE) {
          st = reference_brdf_samples(ctx, &hit, texel, wi,
                                      core_hash64(o->seed ^ 0x5851f42d4c957f2dULL, gpix),
                                      (uint64_t)s, &b.acc[3 * p], brdf_evals, err);
          continue;
        }
        int T = texture_latent_colours(&tex->layout);
        float sg[3], wg[3];
        for (int k = 0; k < T; k++)
          texel_proxy(tex, texel, k, &sg[k], &wg[k]);
        vec3 bo;
        double pb;
        if (render_proxy_mix_sample(T, sg, wg, wi, ub, &bo, &pb) && bo.z > 1e-4) {
          bo = v3_normalize(bo);
          vec3 bd = render_to_world(&hit, bo);
          if (render_camera_occluded(&ctx->cam, &hit, bd, INFINITY)) continue;
          double le[3], mis = render_power_heuristic(pb, render_env_pdf(ctx->env, bd));
          render_env_radiance(ctx->env, bd, le);
          query *q = &b.q[push(&b, &nq, p, slot, wi, bo)];
          for (int k = 0; k < 3; k++)
            q->factor[k] = le[k] * bo.z * mis / pb;
        }
      }
    }
    if (st == NBRDF_OK)
      st = eval_queries(ctx, &b, nq, b.texel,
                        core_hash64(core_hash64(o->seed, (uint64_t)tile), (uint64_t)s0), decoded,
                        decode_seconds, brdf_evals, err);
  }
  for (int p = 0; st == NBRDF_OK && p < npix; p++) {
    size_t at = 3 * ((size_t)(y0 + p / w) * o->width + (size_t)(x0 + p % w));
    for (int k = 0; k < 3; k++)
      rgb[at + k] = (float)(b.acc[3 * p + k] / spp);
  }
  buf_free(&b);
  return st;
}
