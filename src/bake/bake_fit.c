#include "bake/bake_fit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_audit_rule.h"
#include "bake/bake_select.h"
#include "core/error.h"
#include "model/autodecoder.h"
#include "model/bundle.h"
#include "train/energy_reference.h"
#include "train/trainer.h"

void bake_correction_free(bake_correction *c) {
  free(c->tuples);
  free(c->delta);
  model_decoder_destroy(c->decoder);
  memset(c, 0, sizeof *c);
}

const model_decoder *bake_correction_decoder(const bake_correction *c, const nbrdf_model *model) {
  return c && c->decoder ? c->decoder : model->decoder;
}

static nbrdf_status clone_decoder(const model_decoder *src, model_decoder **out, nbrdf_error *err) {
  nbrdf_status st = model_decoder_create(&src->cfg, 0, out, err);
  if (st != NBRDF_OK) return st;
  memcpy(nn_params((*out)->nn), nn_params_const(src->nn), sizeof(float) * nn_param_count(src->nn));
  return NBRDF_OK;
}

typedef struct fit_run {
  model_fit *fit;
  const model_samples *ms;
  train_energy *energy; /* NULL: no energy term */
  const float *z;
} fit_run;

nbrdf_status bake_fit_step(model_fit *fit, const model_samples *ms, train_energy *energy,
                           const float *z, int64_t step, double *loss, nbrdf_error *err) {
  nbrdf_status st = model_fit_gradient(fit, ms, step, loss, err);
  double penalty = 0.0;
  if (st == NBRDF_OK && energy && step % BAKE_FIT_ENERGY_EVERY == 0)
    st = train_energy_add_fit(energy, fit, z, step, &penalty, err);
  if (st == NBRDF_OK) *loss += penalty;
  return st;
}

nbrdf_status bake_fit_energy_create(const model_decoder *dec, const train_samples *samples,
                                    float lambda, uint64_t seed, train_energy **out,
                                    nbrdf_error *err) {
  *out = NULL;
  if (!(lambda > 0.0f)) return NBRDF_OK;
  model_energy_options eo = MODEL_ENERGY_OPTIONS_DEFAULT;
  eo.lambda = lambda * BAKE_FIT_ENERGY_EVERY; /* applied every BAKE_FIT_ENERGY_EVERY steps */
  /* The audit's angles and rule (bake_audit_rule.h): what the held-out check's guard measures. */
  eo.n_theta = BAKE_AUDIT_N_THETA;
  for (int t = 0; t < BAKE_AUDIT_N_THETA; t++)
    eo.theta_deg[t] = bake_audit_theta_deg[t];
  eo.polar_rings = BAKE_FIT_ENERGY_RINGS, eo.polar_phi = BAKE_AUDIT_POLAR_PHI;
  eo.seed = seed;
  size_t n = samples->n_brdfs;
  return train_energy_create(dec, samples, &eo,
                             n < BAKE_FIT_ENERGY_BRDFS ? (int)(n ? n : 1) : BAKE_FIT_ENERGY_BRDFS,
                             out, err);
}

static nbrdf_status fit_gradient(void *user, int64_t step, double *loss, nbrdf_error *err) {
  fit_run *f = user;
  return bake_fit_step(f->fit, f->ms, f->energy, f->z, step, loss, err);
}

/* `steps` steps of one fit in the shared trainer (in memory: a bake's fit is short and
 * restarts with the bake), ticking stage "fit" from `done0` of `total`. Learning rates
 * halve every third of the run. */
static nbrdf_status fit_steps(model_decoder *dec, size_t n, float *z, const model_fit_options *o,
                              int steps, const model_samples *ms, train_energy *energy,
                              const bake_fit_settings *s, int done0, int total,
                              nbrdf_error *err) {
  fit_run f = {NULL, ms, energy, z};
  nbrdf_status st = model_fit_create(dec, n, z, o, &f.fit, err);
  if (st != NBRDF_OK) return st;
  int decay = steps / 3 > 0 ? steps / 3 : 0;
  trainer_group groups[2] = {
      {"latents", "adam.latents.m", "adam.latents.v", z, model_fit_grad_latent(f.fit),
       model_fit_latent_count(f.fit), o->lr_latent, decay, 0.5f},
      {"decoder.params", "adam.weights.m", "adam.weights.v", nn_params(dec->nn),
       model_fit_grad_weights(f.fit), nn_param_count(dec->nn), o->lr_weights, decay, 0.5f}};
  trainer_options to = TRAINER_OPTIONS_DEFAULT;
  to.steps = steps;
  to.stage = "fit";
  to.cancel = s->cancel;
  to.ticker = s->ticker;
  to.progress_offset = done0, to.progress_total = total;
  trainer_fit fit = {.user = &f, .gradient = fit_gradient};
  trainer_result r;
  /* Frozen decoder (lr_weights 0): one group, the fit never writes its weights. */
  st = trainer_run(&to, &fit, groups, o->lr_weights > 0.0f ? 2 : 1, NULL, 0, NULL, 0, &r, err);
  if (st == NBRDF_ERR_CANCELLED)
    st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled during the fit (step %d of %d)",
                   done0 + (int)r.steps_done, total);
  model_fit_destroy(f.fit);
  return st;
}

/* The fade radius: twice the largest nearest-neighbour distance among the
 * fitted tuples (so the corrections cover the region they were picked to
 * cover, and fade beyond it); 0 (no fade) for a single tuple. */
static float fade_radius(const bake_correction *c) {
  float worst = 0.0f;
  for (size_t i = 0; i < c->n; i++) {
    float best = 1e30f;
    for (size_t j = 0; j < c->n; j++)
      if (j != i) {
        float d = bake_tuple_distance2(&c->tuples[i], &c->tuples[j], c->lo, c->hi);
        if (d < best) best = d;
      }
    if (best < 1e30f && best > worst) worst = best;
  }
  return worst > 0.0f ? 2.0f * sqrtf(worst) : 0.0f;
}

nbrdf_status bake_fit_run(const nbrdf_model *model, const bake_tuple *t, size_t n,
                          const train_samples *samples, const bake_fit_settings *s,
                          bake_correction *c, nbrdf_error *err) {
  memset(c, 0, sizeof *c);
  const int D = nbrdf_model_latent_dim(model);
  c->latent_dim = D;
  c->n = n;
  model_material_ranges(model, c->lo, c->hi);
  c->tuples = malloc(sizeof *c->tuples * (n ? n : 1));
  c->delta = malloc(sizeof(float) * n * D + 1);
  float *net = malloc(sizeof(float) * n * (D + 2) + 1), *z = malloc(sizeof(float) * n * D + 1);
  nbrdf_status st = NBRDF_OK;
  if (!c->tuples || !c->delta || !net || !z)
    st = core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for the fit");
  if (st == NBRDF_OK) {
    memcpy(c->tuples, t, sizeof *t * n);
    st = bake_tuples_evaluate(model, t, NULL, n, net, err);
  }
  for (size_t k = 0; st == NBRDF_OK && k < n; k++)
    memcpy(z + k * D, net + k * (D + 2), sizeof(float) * D);
  model_samples ms = train_samples_view(samples);
  int total = s->project_steps + s->joint_steps;
  model_fit_options o = MODEL_FIT_OPTIONS_DEFAULT;
  o.rows_per_brdf = s->rows_per_brdf;
  o.seed = s->seed;
  o.lr_latent = 1e-2f;
  /* Frozen decoder: the fit never writes its weights (as nbrdf_model_project). */
  if (st == NBRDF_OK && s->project_steps > 0)
    st = fit_steps(model->decoder, n, z, &o, s->project_steps, &ms, NULL, s, 0, total, err);
  if (st == NBRDF_OK && s->joint_steps > 0) {
    st = clone_decoder(model->decoder, &c->decoder, err);
    o.lr_latent = 5e-3f;
    o.lr_weights = 5e-4f;
    o.seed = s->seed + 1;
    train_energy *energy = NULL;
    if (st == NBRDF_OK)
      st = bake_fit_energy_create(c->decoder, samples, s->energy, s->seed + 2, &energy, err);
    if (st == NBRDF_OK)
      st = fit_steps(c->decoder, n, z, &o, s->joint_steps, &ms, energy, s, s->project_steps,
                     total, err);
    train_energy_destroy(energy);
  }
  if (st == NBRDF_OK && s->ticker && core_ticker_tick(s->ticker, "fit", total, total, 1))
    st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled after the fit");
  for (size_t k = 0; st == NBRDF_OK && k < n; k++)
    for (int d = 0; d < D; d++)
      c->delta[k * D + d] = z[k * D + d] - net[k * (D + 2) + d];
  if (st == NBRDF_OK) c->radius = fade_radius(c);
  free(net), free(z);
  if (st != NBRDF_OK) bake_correction_free(c);
  return st;
}

void bake_correct_latents(const bake_correction *c, const bake_tuple *t, const size_t *idx,
                          size_t n, float *out, size_t stride) {
  if (!c || c->n == 0) return;
  const int D = c->latent_dim;
  enum { K = BAKE_FIT_NEIGHBOURS };
  for (size_t k = 0; k < n; k++) {
    size_t i = idx ? idx[k] : k;
    const bake_tuple *q = &t[i];
    float *z = out + i * stride;
    size_t near[K] = {0};
    float d2[K] = {0};
    int m = 0;
    for (size_t j = 0; j < c->n; j++) {
      float d = bake_tuple_distance2(q, &c->tuples[j], c->lo, c->hi);
      if (m < K || d < d2[m - 1]) {
        int p = m < K ? m++ : K - 1;
        while (p > 0 && d2[p - 1] > d) {
          d2[p] = d2[p - 1], near[p] = near[p - 1];
          p--;
        }
        d2[p] = d, near[p] = j;
      }
    }
    if (d2[0] == 0.0f) { /* a fitted tuple itself: its own fitted latent */
      for (int d = 0; d < D; d++)
        z[d] += c->delta[near[0] * D + d];
      continue;
    }
    double wsum = 0.0, w[K];
    for (int a = 0; a < m; a++)
      wsum += w[a] = 1.0 / d2[a];
    double fade = c->radius > 0.0f ? exp(-d2[0] / ((double)c->radius * c->radius)) : 1.0;
    for (int d = 0; d < D; d++) {
      double v = 0.0;
      for (int a = 0; a < m; a++)
        v += w[a] * c->delta[near[a] * D + d];
      z[d] += (float)(fade * v / wsum);
    }
  }
}
