/* The settings and the result of a layering-network fit, shared by its two
 * losses (train_layering.h) and the trainer scaffold they run in
 * (layering_trainer.h), which needs them and nothing else of the fits. */
#ifndef NBRDF_TRAIN_LAYERING_SETTINGS_H
#define NBRDF_TRAIN_LAYERING_SETTINGS_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include "model/energy.h"
#include "model/layering.h"
#include "model/loss.h"
#include "nbrdf/status.h"

typedef struct train_layering_settings {
  const char *preset; /* model/layering.h presets */
  int epochs, batch;
  float lr;
  int decay_every; /* epochs */
  float decay_gamma;
  int validation_every;
  uint64_t seed;
  const char *log_path;       /* CSV: epoch, train_loss, val_loss, val_decoded, lr (may be NULL) */
  nbrdf_progress_fn progress; /* stage "train layering", epochs */
  void *user;
  /* Decoded loss only: */
  int rows_per_pair;          /* samples drawn per pair per step */
  model_loss_kind loss;       /* the decoder's training loss */
  const model_layering *init; /* start from these weights (same preset), else random */
  /* Both losses (train/trainer.h): */
  const char *checkpoint;        /* resumable state, written atomically (may be NULL) */
  double checkpoint_seconds;     /* at most this long between checkpoints */
  double max_seconds;            /* stop (checkpointed) after this long; 0 = no limit */
  int64_t stop_at_step;          /* stop (checkpointed) after this many batches; 0 = none */
  volatile sig_atomic_t *cancel; /* may be NULL */
  /* Energy penalty on the decoded albedo of the first energy_brdfs pairs of
   * each batch (train/energy_reference.h); λ = 0 is off. */
  model_energy_options energy;
  int energy_brdfs;
} train_layering_settings;

#define TRAIN_LAYERING_SETTINGS_DEFAULT                                                            \
  {                                                                                                \
    "small", 400, 128, 1e-3f, 150, 0.5f, 10, 1u, NULL, NULL, NULL, 64, MODEL_LOSS_L1_LOG1P, NULL,  \
        NULL, 300.0, 0.0, 0, NULL, MODEL_ENERGY_OPTIONS_DEFAULT, 8                                \
  }

typedef struct train_layering_result {
  size_t pairs, validation_pairs;
  double train_loss, val_loss, target_mean_square; /* val_loss / target_mean_square: relative */
  double val_decoded;        /* decoded loss of the held-out pairs (NaN without a decoder) */
  double val_decoded_oracle; /* same with the run's own latents (latent loss only; else NaN) */
  int epochs_done, resumed_from;
  int legacy_resume; /* resumed from a checkpoint made before nbrdf.options */
} train_layering_result;

#endif
