/* Decoder training (paper §3.2/§4.2): the auto-decoder fit of
 * model/autodecoder.h over training data sets, with one latent per BRDF and the
 * decoder's weights learned together, checkpointed and resumable.
 *
 * A run lives in a folder:
 *   checkpoint.safetensors  everything a resume needs (weights, latents, Adam
 *                           moments, step), written atomically
 *   decoder.safetensors     the decoder alone, for bundles and evaluation
 *   log.csv                 step, seconds, train loss, validation loss, lr
 * Every step is a pure function of (settings, data, step), so an interrupted
 * run resumed from its checkpoint reaches the same weights as one that never
 * stopped (for a fixed OpenBLAS thread count).
 *
 * Validation: BRDFs of the held-out `rep` family (indices from
 * TRAIN_VALIDATION_FIRST, apart from the ones `nbrdf evaluate` reports) are
 * projected with the decoder frozen at each checkpoint; their mean loss over
 * all samples is the log's val_loss. */
#ifndef NBRDF_TRAIN_DECODER_H
#define NBRDF_TRAIN_DECODER_H

#include <signal.h>
#include <stdint.h>

#include "model/decoder.h"
#include "model/energy.h"
#include "model/loss.h"
#include "nbrdf/model.h"
#include "nbrdf/status.h"

#define TRAIN_VALIDATION_FIRST 100000u

typedef struct train_decoder_settings {
  const char *const *data; /* data set paths (nbrdf dataset) */
  int n_data;
  const char *run_dir;
  model_decoder_config arch; /* from a preset or model_decoder_config_make */
  int64_t steps;             /* total steps of the run */
  double max_seconds;        /* stop (checkpointed, resumable) after this long; 0 = no limit */
  int64_t stop_at_step;      /* stop (checkpointed, resumable) after this step; 0 = none */
  int rows_per_brdf;         /* samples per BRDF per step */
  float lr_weights, lr_latent, latent_l2;
  int decay_every;
  float decay_gamma;
  model_loss_kind loss;
  /* Loss weight of BRDF b ∝ max(m_b, 0.01)^−brdf_weight, m_b = the mean of
   * log(1 + f) over its samples, normalised to mean 1: 0 (default) weighs
   * every sample alike; > 0 moves the fit towards equal RELATIVE error per
   * BRDF, which is what the lobe error measures (dim dielectrics otherwise
   * count for little). */
  double brdf_weight;
  uint64_t seed;
  /* A fine-tune (NULL: none): the decoder starts from this bundle's weights (arch must be its
   * decoder's: it replaces `arch`) and each BRDF's latent from the one the bundle gives its
   * parameters (train/params_latent.h), so the run starts where the bundle is, not from noise. */
  const nbrdf_model *init;
  /* Energy penalty (model/energy.h, train/energy_reference.h): λ = 0 is off;
   * energy_brdfs latents are penalised per step. */
  model_energy_options energy;
  int energy_brdfs;
  double checkpoint_seconds;  /* at most this long between checkpoints */
  int log_every;              /* steps between log lines */
  int validation_brdfs;       /* held-out BRDFs projected at checkpoints (0 = none) */
  nbrdf_progress_fn progress; /* stage "train decoder", done/total in steps */
  void *user;
  volatile sig_atomic_t *cancel; /* may be NULL */
} train_decoder_settings;

#define TRAIN_DECODER_CHECKPOINT_FORMAT "nbrdf-train-decoder-checkpoint"

/* The defaults (arch: the "medium" preset). */
void train_decoder_settings_default(train_decoder_settings *s);

typedef struct train_decoder_result {
  int64_t steps_done, resumed_from;
  double train_loss, val_loss; /* last measured (val: NaN when not measured) */
  int finished;                /* all steps done */
  int legacy_resume;           /* resumed from a checkpoint made before nbrdf.options */
} train_decoder_result;

/* Runs (or resumes) the training in settings->run_dir (train/trainer.h: the
 * checkpoint records the settings a resume must share, nbrdf.options). Returns
 * NBRDF_ERR_CANCELLED when stopped by the progress callback, the cancel flag,
 * stop_at_step or max_seconds,
 * after writing a checkpoint (the same call resumes). */
nbrdf_status train_decoder_run(const train_decoder_settings *s, train_decoder_result *r,
                               nbrdf_error *err);

#endif
