/* The decoder run's checkpoint (train_decoder.h): one safetensors file with
 * the decoder's parameters, the latents, both Adam optimisers' moments and the
 * step, so that a resume is exact. Metadata ties it to its architecture and
 * data: a checkpoint of another architecture or other data sets is refused. */
#ifndef NBRDF_TRAIN_CHECKPOINT_H
#define NBRDF_TRAIN_CHECKPOINT_H

#include <stddef.h>
#include <stdint.h>

#include "model/autodecoder.h"
#include "train/samples.h"

#define TRAIN_CHECKPOINT_FORMAT "nbrdf-train-decoder-checkpoint"

/* The data a run was trained on, as one string (the files' checksums in
 * order), for checkpoints to refuse other data. */
void train_checkpoint_data_key(const train_samples *data, char *out, size_t size);

/* Writes `path` atomically. */
nbrdf_status train_checkpoint_save(const char *path, const model_decoder *dec, model_fit *fit,
                                   const float *latents, size_t n_brdfs, const train_samples *data,
                                   nbrdf_error *err);

/* Restores into a freshly created decoder / fit of the same architecture and
 * data; *step gets the step reached. */
nbrdf_status train_checkpoint_load(const char *path, model_decoder *dec, model_fit *fit,
                                   float *latents, size_t n_brdfs, const train_samples *data,
                                   int64_t *step, nbrdf_error *err);

#endif
