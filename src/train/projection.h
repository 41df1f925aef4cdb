/* Projection in the trainer (train/trainer.h): latents fitted to sample sets
 * with the decoder frozen. Several sets run as one trainer run, each with its
 * own gradient engine (model/autodecoder.h) and Adam group, so their steps are
 * exactly those of separate runs while one checkpoint covers them all
 * (`nbrdf train tables` projects its two tables that way). The public
 * nbrdf_model_project runs one set in memory (train/project_api.c). */
#ifndef NBRDF_TRAIN_PROJECTION_H
#define NBRDF_TRAIN_PROJECTION_H

#include "model/autodecoder.h"
#include "train/trainer.h"

#define TRAIN_PROJECTION_MAX_SETS 4

typedef struct train_projection {
  model_loss_kind loss;
  int rows_per_brdf;
  float lr;
  int decay_every;
  float decay_gamma;
  uint64_t seed;
  int steps;
  int max_batch; /* rows per GEMM batch (it orders the sums); 0 = MODEL_FIT_OPTIONS_DEFAULT's */
} train_projection;

/* Fits latents[i] [sets[i].n_brdfs × D] (from their values on entry) to
 * sets[i]. `base` gives the trainer's checkpoint, log, progress and limits
 * (NULL: in memory, silent); its options get the projection's appended. */
nbrdf_status train_project_sets(model_decoder *dec, int n_sets, const model_samples *sets,
                                float *const *latents, const train_projection *p,
                                const trainer_options *base, trainer_result *r, nbrdf_error *err);

/* The data term over ALL of `set`'s samples at `latents` (model_fit_eval_loss),
 * with the fit options train_project_sets gives p (the same loss and batches):
 * per BRDF into per_brdf and the mean over rows into *mean (either may be NULL). */
nbrdf_status train_projection_loss(model_decoder *dec, const model_samples *set, float *latents,
                                   const train_projection *p, double *per_brdf, double *mean,
                                   nbrdf_error *err);

#endif
