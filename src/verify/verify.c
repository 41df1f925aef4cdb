/* nbrdf_verify: opens the texture and the parameter sources, refuses a
 * texture of another model or format, and compares each chosen texel's
 * decoded lobe images with the ground truth of its footprint. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake/bake_audit.h"
#include "bake/bake_sources.h"
#include "core/error.h"
#include "core/progress.h"
#include "model/material.h"
#include "texture/latent_exr.h"
#include "texture/latent_settings.h"
#include "texture/mip_chain.h"
#include "verify/verify_internal.h"

typedef struct verify_run {
  const nbrdf_model *model;
  nbrdf_model *decoding; /* model, with the texture's own decoder when it has one */
  const char *path;
  nbrdf_verify_options o;
  nbrdf_roughness roughness;
  texture_latent_reader *reader;
  const texture_latent_info *info;
  texture_param_source *src[NBRDF_BAKE_PARAM_COUNT];
  int colours;
  verify_refs *refs;
  verify_decoder *dec;
  float *texel;                         /* one texel of the file, all channels */
  double *ref, *approx, *run_a, *run_b; /* colours × VERIFY_SET each */
  nbrdf_verify_report *rep;
  core_ticker ticker;
  size_t texel_index; /* of the texel being compared, for the progress */
  int references;     /* references computed for it so far */
  int last_image;
  float lo[NBRDF_BAKE_PARAM_COUNT], hi[NBRDF_BAKE_PARAM_COUNT]; /* the model's trained ranges */
  int fast; /* the texture is at the fast level (its alpha clamped to the trained range) */
} verify_run;

/* Between chunks of a reference's random walks: the progress moves within a
 * texel, by lobe images (2 x VERIFY_N_THETA per reference, one reference per colour channel
 * at level 0; a footprint's texels for coarser levels, capped below the next). */
static int reference_tick(void *user, int image) {
  verify_run *v = user;
  if (image < v->last_image) v->references++;
  v->last_image = image;
  const double per = 2.0 * VERIFY_N_THETA;
  double f = (v->references * per + image) / (per * v->colours);
  return core_ticker_tick(&v->ticker, "verify", (double)v->texel_index + (f < 0.95 ? f : 0.95),
                          (double)v->rep->n_texels, 0);
}

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static nbrdf_status open_texture(verify_run *v, nbrdf_error *err) {
  nbrdf_status st = texture_latent_reader_open(&v->reader, v->path, err);
  if (st != NBRDF_OK) return st;
  v->info = texture_latent_reader_info(v->reader);
  /* The reader refuses versions newer than this build's; every older one is
   * decoded as a renderer would: with the texture's own decoder, if any. */
  st = texture_latent_reader_model(v->reader, v->model, &v->decoding, err);
  if (st != NBRDF_OK) return st;
  v->colours = texture_latent_colours(&v->info->layout);
  model_material_ranges(v->model, v->lo, v->hi);
  /* A fast texture (no accuracy attribute, level=fast, or a fallback to it) stands for alpha
   * clamped to the trained range; the fitting levels fit alpha down to 0.001 as given. */
  char level[32];
  v->fast = !texture_latent_setting(v->info->accuracy, "level", level, sizeof level) ||
            !strcmp(level, "fast");
  if (v->o.roughness == NBRDF_VERIFY_ROUGHNESS_FROM_TEXTURE) {
    /* Every bake records roughness=; a texture without it (another writer's)
     * is read as alpha, the model's own convention. A value this build does
     * not know would be a guess either way. */
    char value[64];
    int convention = NBRDF_ROUGHNESS_ALPHA;
    if (texture_latent_setting(v->info->settings, "roughness", value, sizeof value) &&
        (convention = model_roughness_parse(value)) < 0)
      return core_fail(err, NBRDF_ERR_FORMAT,
                       "%s: its bake settings have roughness=%s, neither 'alpha' nor "
                       "'perceptual'; pass --roughness",
                       v->path, value);
    v->roughness = (nbrdf_roughness)convention;
  } else
    v->roughness = (nbrdf_roughness)v->o.roughness;
  return NBRDF_OK;
}

static nbrdf_status open_inputs(verify_run *v, const nbrdf_bake_inputs *inputs, nbrdf_error *err) {
  /* The maps are sized as the bake sized them: to the texture's size (a bake
   * with an output size resampled them to it, and then so must this). */
  nbrdf_bake_inputs sized = *inputs;
  const nbrdf_bake_inputs *in = &sized;
  if (!sized.width) sized.width = v->info->width, sized.height = v->info->height;
  nbrdf_status st = bake_open_sources(in, v->src, err);
  if (st != NBRDF_OK) return st;
  int w, h;
  st = texture_param_sources_common_size(v->src, NBRDF_BAKE_PARAM_COUNT, &w, &h, err);
  if (st != NBRDF_OK) return st;
  if (w && (w != v->info->width || h != v->info->height))
    return core_fail(err, NBRDF_ERR_MISMATCH, "the maps are %d x %d but %s is %d x %d", w, h,
                     v->path, v->info->width, v->info->height);
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    if (texture_param_source_channels(v->src[id]) == 3 && v->colours == 1)
      return core_fail(err, NBRDF_ERR_MISMATCH, "%s is RGB but %s is a mono texture",
                       texture_param_source_describe(v->src[id]), v->path);
  return NBRDF_OK;
}

/* The ground truth's parameters of level-0 texel (x, y), channel c. */
static nbrdf_status texel_tuple(verify_run *v, int x, int y, int c, verify_tuple *t,
                                nbrdf_error *err) {
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    texture_param_band band;
    nbrdf_status st = texture_param_source_read_band(v->src[id], y, 1, &band, err);
    if (st != NBRDF_OK) return st;
    t->p[id] = model_material_read(id, v->roughness, texture_param_band_at(&band, x, 0, c));
  }
  return NBRDF_OK;
}

/* References of every colour channel averaged over the footprint of texel
 * (x, y) of `level`: the images are linear in f, so their mean is the lobe
 * image of the mean BRDF. */
static nbrdf_status footprint_reference(verify_run *v, nbrdf_verify_texel *out, nbrdf_error *err) {
  const int W = v->info->width, H = v->info->height;
  int x0, x1, y0, y1;
  texture_mip_footprint(W, out->level, out->x, &x0, &x1);
  texture_mip_footprint(H, out->level, out->y, &y0, &y1);
  verify_point pts[1024];
  int fmax = v->o.footprint_max < 1024 ? v->o.footprint_max : 1024;
  int n = verify_footprint(x0, x1, y0, y1, fmax, pts);
  const size_t S = VERIFY_SET * (size_t)v->colours;
  memset(v->run_a, 0, S * sizeof(double));
  memset(v->run_b, 0, S * sizeof(double));
  memset(out->params, 0, sizeof out->params);
  for (int k = 0; k < n; k++)
    for (int c = 0; c < v->colours; c++) {
      verify_tuple t;
      const double *a, *b;
      nbrdf_status st = texel_tuple(v, pts[k].x, pts[k].y, c, &t, err);
      if (st == NBRDF_OK) st = verify_refs_get(v->refs, &t, &a, &b, &v->rep->clamped, err);
      if (st != NBRDF_OK) return st;
      if (t.p[NBRDF_BAKE_ALPHA1] < v->lo[NBRDF_BAKE_ALPHA1] ||
          t.p[NBRDF_BAKE_ALPHA2] < v->lo[NBRDF_BAKE_ALPHA2])
        v->rep->below_trained_alpha++;
      double *ra = v->run_a + (size_t)c * VERIFY_SET, *rb = v->run_b + (size_t)c * VERIFY_SET;
      for (size_t i = 0; i < VERIFY_SET; i++)
        ra[i] += a[i] / n, rb[i] += b[i] / n;
      for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
        out->params[id][c] += t.p[id] / (float)n;
    }
  for (size_t i = 0; i < S; i++)
    v->ref[i] = 0.5 * (v->run_a[i] + v->run_b[i]);
  out->footprint = (x1 - x0) * (y1 - y0);
  return NBRDF_OK;
}

static nbrdf_status compare_texel(verify_run *v, nbrdf_verify_texel *out, nbrdf_error *err) {
  double t0 = now();
  nbrdf_status st = footprint_reference(v, out, err);
  if (st != NBRDF_OK) return st;
  double t1 = now();
  v->rep->reference_seconds += t1 - t0;
  st = texture_latent_reader_read(v->reader, out->level, out->x, out->y, 1, 1, v->texel, err);
  if (st != NBRDF_OK) return st;
  const texture_latent_layout *L = &v->info->layout;
  float latent[NBRDF_LATENT_MAX_DIM];
  int finite = 1;
  for (int c = 0; c < v->colours && finite && st == NBRDF_OK; c++) {
    for (int k = 0; k < L->latent_dim; k++)
      latent[k] = v->texel[texture_latent_index_latent(L, c, k)];
    st = verify_decode(v->dec, latent, v->approx + (size_t)c * VERIFY_SET, &finite, err);
  }
  if (st != NBRDF_OK) {
    core_error_prefix(err, "%s: level %d texel (%d, %d): ", v->path, out->level, out->x, out->y);
    return st;
  }
  v->rep->decode_seconds += now() - t1;
  const size_t S = VERIFY_SET * (size_t)v->colours;
  out->reference_noise = lobe_l1_error(S, v->run_a, v->run_b);
  out->max_albedo = NAN;
  if (!finite) { /* a damaged latent: the worst possible texel, not a crash */
    out->lobe_error = out->albedo_error = INFINITY;
    return NBRDF_OK;
  }
  /* Energy: each channel's latent with its stored proxy lobe. */
  for (int c = 0; c < v->colours && st == NBRDF_OK; c++) {
    for (int k = 0; k < L->latent_dim; k++)
      latent[k] = v->texel[texture_latent_index_latent(L, c, k)];
    float sigma = L->proxy ? v->texel[texture_latent_index_sigma(L, c)] : 0.0f;
    double m = NAN;
    st = bake_albedo_precise(v->decoding, NULL, 1, latent, L->proxy && sigma > 0.0f ? &sigma : NULL,
                             &m, NULL, err);
    if (st == NBRDF_OK && (isnan(out->max_albedo) || m > out->max_albedo)) out->max_albedo = m;
  }
  if (st != NBRDF_OK) return st;
  if (isnan(v->rep->max_albedo) || out->max_albedo > v->rep->max_albedo)
    v->rep->max_albedo = out->max_albedo;
  out->lobe_error = lobe_l1_error(S, v->ref, v->approx);
  out->albedo_error =
      lobe_albedo_error(NBRDF_LOBE_RES, VERIFY_N_THETA * v->colours, v->ref, v->approx, NULL);
  return NBRDF_OK;
}

/* Chooses the texels of every level to verify into rep->texels. */
static nbrdf_status plan(verify_run *v, int first, int last, nbrdf_error *err) {
  nbrdf_verify_report *rep = v->rep;
  for (int level = first; level <= last; level++) {
    int w, h;
    nbrdf_status st = texture_latent_reader_level_size(v->reader, level, &w, &h, err);
    if (st != NBRDF_OK) return st;
    verify_point *p = NULL;
    size_t n = verify_select(w, h, v->o.texels, v->o.seed, level, &p);
    nbrdf_verify_texel *t = n ? realloc(rep->texels, (rep->n_texels + n) * sizeof *t) : NULL;
    if (!t) {
      free(p);
      return core_fail(err, NBRDF_ERR_MEMORY, "verify: out of memory for %zu texels", n);
    }
    rep->texels = t;
    for (size_t i = 0; i < n; i++) {
      nbrdf_verify_texel *e = &t[rep->n_texels++];
      memset(e, 0, sizeof *e);
      e->level = level, e->x = p[i].x, e->y = p[i].y;
    }
    free(p);
  }
  return NBRDF_OK;
}

static nbrdf_status run(verify_run *v, const nbrdf_bake_inputs *in, nbrdf_error *err) {
  nbrdf_status st = open_texture(v, err);
  if (st == NBRDF_OK) st = open_inputs(v, in, err);
  if (st != NBRDF_OK) return st;
  const int levels = v->info->levels;
  if (v->o.level >= levels)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s has %d mip level%s (0..%d); there is no level %d",
                     v->path, levels, levels == 1 ? "" : "s", levels - 1, v->o.level);
  int first = v->o.level == NBRDF_VERIFY_ALL_LEVELS ? 0 : v->o.level;
  int last = v->o.level == NBRDF_VERIFY_ALL_LEVELS ? levels - 1 : v->o.level;
  const size_t S = VERIFY_SET * (size_t)v->colours;
  v->refs = verify_refs_create(v->o.walks, v->o.seed, v->o.threads);
  v->dec = verify_decoder_create(v->decoding);
  v->texel = malloc(sizeof(float) * (size_t)v->info->channels);
  v->ref = malloc(4 * S * sizeof(double));
  v->rep = calloc(1, sizeof *v->rep);
  if (!v->refs || !v->dec || !v->texel || !v->ref || !v->rep)
    return core_fail(err, NBRDF_ERR_MEMORY, "verify: out of memory");
  v->approx = v->ref + S, v->run_a = v->ref + 2 * S, v->run_b = v->ref + 3 * S;
  nbrdf_verify_report *rep = v->rep;
  rep->width = v->info->width, rep->height = v->info->height;
  rep->levels = levels, rep->colours = v->colours;
  rep->walks = v->o.walks, rep->seed = v->o.seed;
  nbrdf_model_own_decoder(v->decoding, &rep->decoder);
  rep->decoder.bytes = NULL; /* the model's, gone with it */
  rep->max_albedo = NAN;
  rep->alpha_clamped_by_texture = v->fast;
  rep->alpha_trained_min = v->lo[NBRDF_BAKE_ALPHA1];
  verify_damage damage;
  st = verify_scan(v->reader, &damage, err);
  rep->nonfinite = damage.texels;
  if (damage.texels)
    rep->nonfinite_level = damage.level, rep->nonfinite_x = damage.x, rep->nonfinite_y = damage.y;
  if (st == NBRDF_OK) st = plan(v, first, last, err);
  core_ticker_init(&v->ticker, v->o.progress, v->o.user, v->o.cancel);
  verify_refs_set_cancel(v->refs, v->o.cancel, reference_tick, v);
  for (size_t i = 0; st == NBRDF_OK && i < rep->n_texels; i++) {
    v->texel_index = i, v->references = 0, v->last_image = 0;
    if (core_ticker_tick(&v->ticker, "verify", (double)i, (double)rep->n_texels, i == 0))
      return core_fail(err, NBRDF_ERR_CANCELLED, "verify: cancelled after %zu of %zu texels", i,
                       rep->n_texels);
    st = compare_texel(v, &rep->texels[i], err);
    if (st == NBRDF_ERR_CANCELLED) /* inside a ground truth */
      st = core_fail(err, NBRDF_ERR_CANCELLED, "verify: cancelled after %zu of %zu texels", i,
                     rep->n_texels);
  }
  if (st != NBRDF_OK) return st;
  if (core_ticker_tick(&v->ticker, "verify", (double)rep->n_texels, (double)rep->n_texels, 1))
    return core_fail(err, NBRDF_ERR_CANCELLED, "verify: cancelled after the last texel");
  rep->n_levels = last - first + 1;
  rep->per_level = malloc(sizeof *rep->per_level * (size_t)rep->n_levels);
  if (!rep->per_level) return core_fail(err, NBRDF_ERR_MEMORY, "verify: out of memory");
  for (int l = first; l <= last; l++)
    rep->per_level[l - first] = verify_summarise(rep->texels, rep->n_texels, l);
  rep->overall = verify_summarise(rep->texels, rep->n_texels, NBRDF_VERIFY_ALL_LEVELS);
  rep->references = verify_refs_count(v->refs);
  rep->decoded = verify_decoder_distinct(v->dec);
  rep->decoder_queries = verify_decoder_queries(v->dec);
  return NBRDF_OK;
}

nbrdf_status nbrdf_verify(const nbrdf_model *model, const char *texture,
                          const nbrdf_bake_inputs *inputs, const nbrdf_verify_options *options,
                          nbrdf_verify_report **report, nbrdf_error *err) {
  if (report) *report = NULL;
  if (!model || !texture || !*texture || !inputs || !report)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "verify: model, texture, inputs and report are required");
  verify_run v;
  memset(&v, 0, sizeof v);
  v.model = model, v.path = texture;
  v.o = (nbrdf_verify_options)NBRDF_VERIFY_OPTIONS_DEFAULT;
  if (options) v.o = *options;
  if (v.o.texels < 1 || v.o.walks < 1 || v.o.footprint_max < 1 || v.o.threads < 0 ||
      v.o.level < NBRDF_VERIFY_ALL_LEVELS ||
      (v.o.roughness != NBRDF_VERIFY_ROUGHNESS_FROM_TEXTURE &&
       v.o.roughness != NBRDF_ROUGHNESS_ALPHA && v.o.roughness != NBRDF_ROUGHNESS_PERCEPTUAL))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "verify: texels (%d), walks (%d), footprint_max (%d) must be >= 1, threads "
                     "(%d) >= 0, level (%d) >= -1, roughness (%d) known",
                     v.o.texels, v.o.walks, v.o.footprint_max, v.o.threads, v.o.level,
                     v.o.roughness);
  nbrdf_status st = run(&v, inputs, err);
  if (st == NBRDF_OK) {
    *report = v.rep;
    v.rep = NULL;
  }
  nbrdf_verify_report_free(v.rep);
  texture_latent_reader_close(v.reader);
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    texture_param_source_free(v.src[id]);
  verify_refs_free(v.refs);
  verify_decoder_free(v.dec);
  nbrdf_model_destroy(v.decoding);
  free(v.texel);
  free(v.ref);
  return st;
}
