/* The fit of the accuracy levels: latents of the selected tuples projected
 * onto their ground truth with the decoder frozen (FITTED), then, for
 * SPECIALISED, a copy of the decoder fine-tuned together with them (the
 * auto-decoder step of model/autodecoder.h, restricted to the scene). Both
 * start from the layering network's latents, so a short fit only moves them
 * as far as the truth asks.
 *
 * The correction (fitted latent − network latent) is known at the fitted
 * tuples; every other tuple of the texture gets the inverse-distance
 * weighted mean of the corrections of its BAKE_FIT_NEIGHBOURS nearest fitted
 * tuples in the normalised parameter space, faded out with distance
 * (docs/BAKE.md, "Accuracy levels", says why this rather than fine-tuning the
 * layering network). */
#ifndef NBRDF_BAKE_BAKE_FIT_H
#define NBRDF_BAKE_BAKE_FIT_H

#include <signal.h>
#include <stddef.h>

#include "bake/bake_tuple.h"
#include "core/progress.h"
#include "model/decoder.h"
#include "train/samples.h"

#define BAKE_FIT_NEIGHBOURS 4

typedef struct bake_fit_settings {
  int project_steps;  /* frozen-decoder steps */
  int joint_steps;    /* decoder + latents steps (0: FITTED) */
  int rows_per_brdf;  /* samples drawn per tuple per step */
  uint64_t seed;
  core_ticker *ticker; /* stage "fit", done/total in steps; may be NULL */
  volatile sig_atomic_t *cancel;
  /* The joint fine-tune's energy term (model/energy.h through train/energy_reference.h): its
   * weight λ (0: off). Each joint step penalises min(n, BAKE_FIT_ENERGY_BRDFS) fitted tuples'
   * decoded directional albedo above min(1, ρ + 2 se + 0.01), ρ their ground truth's
   * (nbrdf_brdf_albedo), by the audit's polar rule of BAKE_FIT_ENERGY_RINGS rings at its six θi (0-89°). Without it
   * a decoder fine-tuned on lobes sharper than it was trained on (α 0.001) matches the lobe
   * samples while its lobe integrates to hundreds (docs/notes/2026-11-29-sharp-alpha.md). */
  float energy;
} bake_fit_settings;

/* Applied on every BAKE_FIT_ENERGY_EVERY-th step with its weight times as much (the same
 * expected gradient for a quarter of its decoder rows: the smallest specialised plan stays
 * under 2 s of the cost model). */
#define BAKE_FIT_ENERGY_EVERY 4
#define BAKE_FIT_ENERGY_BRDFS 8
#define BAKE_FIT_ENERGY_RINGS 12

typedef struct bake_correction {
  int latent_dim;
  size_t n;
  bake_tuple *tuples; /* [n] fitted tuples */
  float *delta;       /* [n x latent_dim] fitted − network latents */
  float lo[NBRDF_BAKE_PARAM_COUNT], hi[NBRDF_BAKE_PARAM_COUNT];
  /* The fade: weight exp(−d²/radius²) of the nearest fitted tuple's
   * distance d (normalised space); 0 = no fade. */
  float radius;
  model_decoder *decoder; /* SPECIALISED: the fine-tuned copy (owned); else NULL */
} bake_correction;

/* Fits the n tuples `t` whose ground truth is `samples` (one BRDF each, in
 * order) and fills `c`. */
nbrdf_status bake_fit_run(const nbrdf_model *model, const bake_tuple *t, size_t n,
                          const train_samples *samples, const bake_fit_settings *s,
                          bake_correction *c, nbrdf_error *err);
void bake_correction_free(bake_correction *c);

struct train_energy;
struct model_fit;
struct model_samples;
/* The joint fine-tune's energy term for `dec` over the fit's BRDFs `samples` (their
 * parameters give the ceilings): *out NULL when lambda <= 0. */
nbrdf_status bake_fit_energy_create(const model_decoder *dec, const train_samples *samples,
                                    float lambda, uint64_t seed, struct train_energy **out,
                                    nbrdf_error *err);
/* One step of the fit's objective, what its trainer calls: the data term of
 * model_fit_gradient and, with `energy` (may be NULL) on every BAKE_FIT_ENERGY_EVERY-th step,
 * the energy term of the BRDFs the step draws (z: the fit's latents), both in the fit's
 * gradients; *loss their sum. */
nbrdf_status bake_fit_step(struct model_fit *fit, const struct model_samples *ms,
                           struct train_energy *energy, const float *z, int64_t step,
                           double *loss, nbrdf_error *err);

/* Adds the carried correction to the latents of n tuples: tuple t[idx[k]]
 * (idx NULL: t[k]) has its latent at out + idx[k] * stride (idx NULL:
 * k * stride). */
void bake_correct_latents(const bake_correction *c, const bake_tuple *t, const size_t *idx,
                          size_t n, float *out, size_t stride);

/* The decoder a texture of this correction is decoded with. */
const model_decoder *bake_correction_decoder(const bake_correction *c, const nbrdf_model *model);

#endif
