#include "bake/bake_level.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_band.h"
#include "core/error.h"
#include "model/bundle.h"

static nbrdf_status fit_none(const nbrdf_model *model, const bake_scene *scenes, size_t n_scenes,
                             const nbrdf_bake_options *o, core_ticker *ticker, bake_fit_result *r,
                             nbrdf_error *err) {
  (void)model, (void)scenes, (void)n_scenes, (void)o, (void)ticker, (void)err;
  memset(r, 0, sizeof *r);
  return NBRDF_OK;
}

static void store_same(const bake_evaluate *e, const float *in, float *out, size_t n) {
  (void)e, (void)in, (void)out, (void)n;
}

/* The proxy of a mip texel is predicted from its averaged latents rather
 * than averaged itself (docs/LATENT-TEXTURE.md, "Mip levels"). */
static nbrdf_status mip_latents(void *user, int level, int y, float *row, int width,
                                nbrdf_error *err) {
  (void)level, (void)y;
  const bake_evaluate *e = user;
  return bake_proxy_from_latents(e->model, &e->stored, row, (size_t)width, err);
}

static nbrdf_status open_fast(const nbrdf_model *model, const bake_fit_result *r,
                              const texture_latent_layout *work, int width, bake_evaluate *e,
                              nbrdf_error *err) {
  (void)r, (void)width, (void)err;
  memset(e, 0, sizeof *e);
  e->model = e->stored_model = model;
  e->work = e->stored = *work;
  e->store = store_same;
  e->mip_row = mip_latents;
  e->stores_work = 1;
  return NBRDF_OK;
}

/* FITTED and SPECIALISED: the correction on every latent; a fine-tuned
 * decoder (SPECIALISED) becomes the model's own decoder, whose bytes the
 * texture then carries (format version 2). */
static nbrdf_status open_fitted(const nbrdf_model *model, const bake_fit_result *r,
                                const texture_latent_layout *work, int width, bake_evaluate *e,
                                nbrdf_error *err) {
  nbrdf_status st = open_fast(model, r, work, width, e, err);
  e->correct = &r->correction;
  if (st == NBRDF_OK && r->correction.decoder) {
    st = model_with_decoder_net(model, r->correction.decoder, &e->owned[0], err);
    if (st == NBRDF_OK) e->model = e->stored_model = e->owned[0];
  }
  return st;
}

/* COMPACT: the band texels are computed as SPECIALISED's, then stored in
 * the basis's coordinates (proxy unchanged). */
static void store_compact(const bake_evaluate *e, const float *in, float *out, size_t n) {
  bake_compact_texels(e->compact, &e->work, in, &e->stored, out, n);
}

/* A compact mip texel's proxy: that of the latent its averaged coordinates
 * stand for. */
static nbrdf_status mip_compact(void *user, int level, int y, float *row, int width,
                                nbrdf_error *err) {
  (void)level, (void)y;
  const bake_evaluate *e = user;
  const texture_latent_layout *L = &e->stored, *W = &e->work;
  const int C = texture_latent_colours(L);
  const int fin = texture_latent_channel_count(L), fw = texture_latent_channel_count(W);
  float coords[BAKE_COMPACT_MAX_DIM], z[NBRDF_LATENT_MAX_DIM];
  for (int x = 0; x < width; x++)
    for (int c = 0; c < C; c++) {
      for (int j = 0; j < e->compact->dim; j++)
        coords[j] = row[x * fin + texture_latent_index_latent(L, c, j)];
      bake_compact_expand(e->compact, coords, z);
      for (int d = 0; d < W->latent_dim; d++)
        e->work_row[x * fw + texture_latent_index_latent(W, c, d)] = z[d];
    }
  nbrdf_status st = bake_proxy_from_latents(e->model, W, e->work_row, (size_t)width, err);
  for (int x = 0; st == NBRDF_OK && x < width; x++)
    for (int c = 0; c < C; c++) {
      row[x * fin + texture_latent_index_sigma(L, c)] =
          e->work_row[x * fw + texture_latent_index_sigma(W, c)];
      row[x * fin + texture_latent_index_w(L, c)] =
          e->work_row[x * fw + texture_latent_index_w(W, c)];
    }
  return st;
}

/* COMPACT: the texture carries the student (the bundle with the student as
 * its own decoder) and K coordinates per colour channel. */
static nbrdf_status open_compact(const nbrdf_model *model, const bake_fit_result *r,
                                 const texture_latent_layout *work, int width, bake_evaluate *e,
                                 nbrdf_error *err) {
  nbrdf_status st = open_fitted(model, r, work, width, e, err);
  if (st == NBRDF_OK) st = model_with_decoder_net(model, r->compact.student, &e->owned[1], err);
  if (st != NBRDF_OK) return st;
  e->stored_model = e->owned[1];
  e->compact = &r->compact;
  e->stored.latent_dim = r->compact.dim;
  e->store = store_compact;
  e->mip_row = mip_compact;
  e->stores_work = 0;
  e->work_row = malloc(sizeof(float) * texture_latent_channel_count(work) * (size_t)width);
  if (!e->work_row) return core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for a band");
  return NBRDF_OK;
}

void bake_evaluate_close(bake_evaluate *e) {
  nbrdf_model_destroy(e->owned[0]);
  nbrdf_model_destroy(e->owned[1]);
  free(e->work_row);
  memset(e, 0, sizeof *e);
}

static void audit_fast(const nbrdf_bake_options *o, const bake_fit_result *r,
                       const bake_evaluate *e, nbrdf_bake_report *rep) {
  (void)o, (void)r, (void)e, (void)rep;
}

static void audit_fitted(const nbrdf_bake_options *o, const bake_fit_result *r,
                         const bake_evaluate *e, nbrdf_bake_report *rep) {
  (void)e;
  /* A budget too small for the level can leave it worse than fast (a compact student
   * of few steps): say so rather than let the texture pass for the better one. */
  if (o->warning && r->heldout_error > r->heldout_error_fast) {
    char msg[512];
    snprintf(msg, sizeof msg,
             "the %s texture's held-out lobe error (%.2f %%) is above the fast level's "
             "(%.2f %%) on the same %zu tuples: give it a larger --budget (this one: %g s)",
             nbrdf_bake_accuracy_name(o->accuracy), 100.0 * r->heldout_error,
             100.0 * r->heldout_error_fast, r->heldout, r->budget);
    o->warning(o->user, msg);
  }
  /* Kept (--no-fallback, a fit baked as asked): the guard's verdict is still said. */
  if (o->warning && bake_fit_creates_energy(r)) {
    char msg[512];
    bake_fit_energy_message(r, o->accuracy, msg, sizeof msg);
    o->warning(o->user, msg);
  }
  if (!rep) return;
  rep->accuracy = o->accuracy;
  bake_fit_result_report(r, rep);
}

static void audit_compact(const nbrdf_bake_options *o, const bake_fit_result *r,
                          const bake_evaluate *e, nbrdf_bake_report *rep) {
  audit_fitted(o, r, e, rep);
  if (!rep) return;
  rep->compact_dim = r->compact.dim;
  rep->decoder_macs = (long long)nbrdf_model_decoder_macs(e->stored_model);
  rep->compact_kept = r->compact.kept;
}

static const bake_level levels[] = {
    {NBRDF_BAKE_FAST, fit_none, open_fast, audit_fast},
    {NBRDF_BAKE_FITTED, bake_accuracy_fit, open_fitted, audit_fitted},
    {NBRDF_BAKE_SPECIALISED, bake_accuracy_fit, open_fitted, audit_fitted},
    {NBRDF_BAKE_COMPACT, bake_accuracy_fit, open_compact, audit_compact},
};

const bake_level *bake_level_of(nbrdf_bake_accuracy a) {
  return (unsigned)a < sizeof levels / sizeof *levels ? &levels[a] : &levels[0];
}
