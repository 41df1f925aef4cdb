/* A training checkpoint on disk (train/trainer.h): one safetensors file with
 * every Adam group's parameters and moments, further tensors and integers,
 * the step reached and the options a resume must share. Written atomically
 * (core/output_file.h through the safetensors writer). */
#ifndef NBRDF_TRAIN_CHECKPOINT_H
#define NBRDF_TRAIN_CHECKPOINT_H

#include <stddef.h>
#include <stdint.h>

#include "train/samples.h"
#include "train/trainer_parts.h"

/* The data a run was trained on, as one string (the files' checksums in
 * order), for checkpoints to refuse other data. */
void train_checkpoint_data_key(const train_samples *data, char *out, size_t size);

/* FNV-1a of an array's bytes, continuing from h (start: TRAIN_HASH_START):
 * the inputs a run was made from (decoder weights, tables, target latents)
 * as an option, so that a resume with other inputs is refused. */
#define TRAIN_HASH_START UINT64_C(0xcbf29ce484222325)
uint64_t train_hash_floats(uint64_t h, const float *x, size_t n);

typedef struct train_checkpoint_parts {
  const char *format, *options;
  const trainer_group *groups;
  nn_adam *const *adams; /* [n_groups], NULL where a group has none */
  int n_groups;
  const trainer_tensor *tensors;
  int n_tensors;
  const trainer_word *words;
  int n_words;
} train_checkpoint_parts;

nbrdf_status train_checkpoint_save(const char *path, const train_checkpoint_parts *p, int64_t step,
                                   nbrdf_error *err);

/* Restores every part and *step. A checkpoint without nbrdf.options is
 * checked by `legacy` (which gives the step; NULL: refused) and *legacy_used
 * set. A different format or option is refused naming it and both values. */
nbrdf_status train_checkpoint_load(const char *path, const train_checkpoint_parts *p,
                                   const trainer_fit *fit, int64_t *step, int *legacy_used,
                                   nbrdf_error *err);

/* The decoder run's latents from its checkpoint (for the layering and sampler
 * trainings, which start from them). */
nbrdf_status train_checkpoint_latents(const char *checkpoint, size_t n_brdfs, int dim,
                                      float *latents, nbrdf_error *err);

#endif
