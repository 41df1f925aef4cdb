/* The gradient engine of fitting latents (and optionally the decoder's
 * weights) to BRDF samples: the auto-decoder loss of the paper's
 * representation training (§3.3: decoder weights and one latent per BRDF
 * learned together) and, with the weights frozen, of projection (a latent per
 * BRDF for a fixed decoder).
 *
 * The gradient of step k: for every BRDF, draw rows_per_brdf of its samples
 * (with replacement, PCG32 stream = k, so a run is reproducible and does not
 * depend on the thread count), evaluate the decoder on [latent | encoding] in
 * GEMM batches, take the loss of loss.h averaged over all drawn rows plus
 * latent_l2 · mean_b ‖z_b‖² (a Gaussian prior on latents, as in DeepSDF's
 * auto-decoder; 0 = none), and back-propagate into the latent part of the
 * input (and the weights when lr_weights > 0).
 *
 * No optimiser here: the one loop (src/train/trainer.h; every fit runs in it,
 * the public projection included) owns Adam, its schedule, checkpoints. */
#ifndef NBRDF_MODEL_AUTODECODER_H
#define NBRDF_MODEL_AUTODECODER_H

#include <stddef.h>
#include <stdint.h>

#include "model/decoder.h"
#include "model/loss.h"

/* Samples grouped by BRDF: BRDF b owns rows offsets[b] .. offsets[b+1]-1 (at
 * least one each). Directions unit with z > 0, f >= 0 finite (the public
 * projection call validates; this layer trusts). */
typedef struct model_samples {
  size_t n_brdfs;
  const size_t *offsets; /* n_brdfs + 1 entries, offsets[0] = 0 */
  const float *wi, *wo;  /* [rows × 3] */
  const float *f;        /* [rows] */
  /* [n_brdfs] weight of each BRDF's rows in the training loss (NULL: all 1);
   * model_fit_eval_loss ignores it, so held-out losses stay comparable. */
  const float *weight;
} model_samples;

typedef struct model_fit_options {
  model_loss_kind loss;
  int rows_per_brdf; /* samples drawn per BRDF per step */
  float lr_latent;   /* learning rate of the latents (for the loop; checked >= 0) */
  float lr_weights;  /* learning rate of the decoder; 0 = decoder frozen (no weight gradient) */
  float latent_l2;   /* prior weight on mean ‖z‖²; 0 = none */
  uint64_t seed;
  int max_batch; /* rows per GEMM batch */
} model_fit_options;

#define MODEL_FIT_OPTIONS_DEFAULT                                                                  \
  { MODEL_LOSS_L1_LOG1P, 256, 1e-2f, 0.0f, 0.0f, 0u, 4096 }

typedef struct model_fit model_fit;

/* Fits `latents` [n_brdfs × D] (borrowed, updated in place) and, when
 * opts->lr_weights > 0, the weights of `dec` (borrowed, updated in place). */
nbrdf_status model_fit_create(model_decoder *dec, size_t n_brdfs, float *latents,
                              const model_fit_options *opts, model_fit **out, nbrdf_error *err);
void model_fit_destroy(model_fit *fit);

/* The loss of the rows step `step` draws (they depend only on the seed and
 * the step) and its gradient with respect to the latents and, when the
 * weights are trained, the weights; nothing is updated.
 * `samples->n_brdfs` must equal the fit's. */
nbrdf_status model_fit_gradient(model_fit *fit, const model_samples *samples, int64_t step,
                                double *loss, nbrdf_error *err);
/* The last gradients: [n_brdfs × D], and [param count] (NULL when frozen);
 * the latents (borrowed at create) and their count. */
float *model_fit_grad_latent(model_fit *fit);
float *model_fit_grad_weights(model_fit *fit);
float *model_fit_latents(model_fit *fit);
size_t model_fit_latent_count(const model_fit *fit);

/* The data term of the loss over ALL samples (no sampling, no update), per
 * BRDF into per_brdf (may be NULL) and averaged over rows into *mean. */
nbrdf_status model_fit_eval_loss(model_fit *fit, const model_samples *samples, double *per_brdf,
                                 double *mean, nbrdf_error *err);

#endif
