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
} bake_fit_settings;

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

/* Adds the carried correction to the latents of n tuples: tuple t[idx[k]]
 * (idx NULL: t[k]) has its latent at out + idx[k] * stride (idx NULL:
 * k * stride). */
void bake_correct_latents(const bake_correction *c, const bake_tuple *t, const size_t *idx,
                          size_t n, float *out, size_t stride);

/* The decoder a texture of this correction is decoded with. */
const model_decoder *bake_correction_decoder(const bake_correction *c, const nbrdf_model *model);

#endif
