/* What a fit hands the trainer and its checkpoints (train/checkpoint.h):
 * the arrays Adam updates and the further state saved with them. */
#ifndef NBRDF_TRAIN_TRAINER_PARTS_H
#define NBRDF_TRAIN_TRAINER_PARTS_H

#include <stddef.h>
#include <stdint.h>

#include "nbrdf/status.h"
#include "nn/safetensors.h"

/* An array Adam updates from its gradient. Tensor names are the checkpoint's
 * (kept from older checkpoints so that those still load). */
typedef struct trainer_group {
  const char *tensor, *m_tensor, *v_tensor;
  float *params;
  const float *grad; /* filled by the fit's gradient each step */
  size_t n;
  float lr;          /* 0: not updated */
  int decay_every;   /* steps between learning-rate decays (0 = never) */
  float decay_gamma; /* factor per decay */
} trainer_group;

/* Further state: a float array checkpointed as is, or an integer (a
 * generator's words, an epoch number). */
typedef struct trainer_tensor {
  const char *name;
  float *data;
  size_t n;
} trainer_tensor;
typedef struct trainer_word {
  const char *name;
  uint64_t *value;
} trainer_word;

typedef struct trainer trainer;

/* Flags of trainer_fit.report. */
enum { TRAINER_SAVING = 1, TRAINER_LAST = 2 };

typedef struct trainer_fit {
  void *user;
  /* Loss of step `step` (0-based) and its gradient into every group's grad. */
  nbrdf_status (*gradient)(void *user, int64_t step, double *loss, nbrdf_error *err);
  /* After every step (`done` steps done, `loss` the step's): the fit's own
   * bookkeeping, evaluation and log rows (trainer_log). TRAINER_SAVING: a
   * checkpoint follows; TRAINER_LAST: the run stops after this step. May be
   * NULL. */
  nbrdf_status (*report)(void *user, trainer *t, int64_t done, double loss, int flags,
                         nbrdf_error *err);
  /* After each checkpoint: the fit's products (e.g. decoder.safetensors). May be NULL. */
  nbrdf_status (*save)(void *user, nbrdf_error *err);
  /* A checkpoint without nbrdf.options (made before it existed): check it the
   * old way and give the step it reached. NULL: such checkpoints are refused. */
  nbrdf_status (*legacy)(void *user, const nn_st_reader *r, int64_t *step, nbrdf_error *err);
} trainer_fit;

#endif
