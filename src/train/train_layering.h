/* Layering training (paper §4): the layering network learns to map (table
 * latent of the top dielectric, table latent of the bottom conductor, A, σT)
 * to the latent the auto-decoder learned for that two-layer BRDF. Inputs are
 * looked up in the base tables exactly as a bake does, so the network also
 * absorbs the tables' interpolation error. Loss: mean squared latent error.
 * One pair in `validation_every` is held out and reported as val_loss. */
#ifndef NBRDF_TRAIN_LAYERING_H
#define NBRDF_TRAIN_LAYERING_H

#include "model/base_table.h"
#include "model/layering.h"
#include "train/samples.h"

typedef struct train_layering_settings {
  const char *preset; /* model/layering.h presets */
  int epochs, batch;
  float lr;
  int decay_every; /* epochs */
  float decay_gamma;
  int validation_every;
  uint64_t seed;
  const char *log_path;       /* CSV: epoch, train_loss, val_loss, lr (may be NULL) */
  nbrdf_progress_fn progress; /* stage "train layering", epochs */
  void *user;
} train_layering_settings;

#define TRAIN_LAYERING_SETTINGS_DEFAULT                                                            \
  { "small", 400, 128, 1e-3f, 150, 0.5f, 10, 1u, NULL, NULL, NULL }

typedef struct train_layering_result {
  size_t pairs, validation_pairs;
  double train_loss, val_loss, target_mean_square; /* val_loss / target_mean_square: relative */
} train_layering_result;

/* `data` and `latents` [data->n_brdfs × D] are the decoder run's BRDFs and
 * their learned latents; its two-layer BRDFs become the training pairs.
 * *out is created here. */
nbrdf_status train_layering_fit(const train_samples *data, const float *latents,
                                const model_base_table tables[2], const train_layering_settings *s,
                                model_layering **out, train_layering_result *r, nbrdf_error *err);

/* Loads a decoder run's latents (its checkpoint) for the data it was trained on. */
nbrdf_status train_checkpoint_latents(const char *checkpoint, size_t n_brdfs, int dim,
                                      float *latents, nbrdf_error *err);

#endif
