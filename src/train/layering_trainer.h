/* What the two layering fits share of the trainer (train/trainer.h): the
 * latent loss (train_layering.c) and the decoded loss
 * (train_layering_decoded_fit.c) each supply the loss and gradient of a
 * batch of pairs, their evaluation at an epoch's end and their checkpoint's
 * identity; this holds the rest once: epochs of batches of the pairs in
 * each epoch's shuffle, the layering network's Adam group with the
 * settings' schedule (decay counted in epochs), the settings' epochs,
 * limits, checkpoint, progress and cancel, and the train loss of an epoch. */
#ifndef NBRDF_TRAIN_LAYERING_TRAINER_H
#define NBRDF_TRAIN_LAYERING_TRAINER_H

#include <stddef.h>
#include <stdint.h>

#include "train/epoch_shuffle.h"
#include "train/layering_settings.h"
#include "train/trainer.h"

typedef struct train_layering_trainer {
  model_layering *net;
  float *grad;                  /* the net's gradient: zeroed before each batch */
  size_t n;                     /* training pairs */
  train_epoch_shuffle *shuffle; /* their order in each epoch */
  const char *format;           /* nbrdf.format of the checkpoint */
  const char *options;          /* nbrdf.options: what a resume must share */
  const char *log_header;       /* the CSV log's header (rows: trainer_log in epoch_end) */
  const trainer_word *words;    /* further state a resume needs (may be NULL) */
  int n_words;
  void *user;
  /* Mean loss of the m pairs idx[] (step `step`), their gradient added to grad. */
  nbrdf_status (*batch)(void *user, const size_t *idx, size_t m, int64_t step, double *loss,
                        nbrdf_error *err);
  /* After epoch `epoch` (1-based; r->train_loss holds its train loss): the
   * fit's evaluation and log row. */
  nbrdf_status (*epoch_end)(void *user, trainer *tr, int epoch, nbrdf_error *err);
  /* trainer_fit.legacy, called with `user` (may be NULL). */
  nbrdf_status (*legacy)(void *user, const nn_st_reader *r, int64_t *step, nbrdf_error *err);
} train_layering_trainer;

/* Batches of s->batch pairs: ceil(n / batch). */
int64_t train_layering_steps_per_epoch(const train_layering_settings *s, size_t n);

/* Runs the fit under s (trainer_run's contract) and fills r's train_loss,
 * resumed_from, epochs_done and legacy_resume. */
nbrdf_status train_layering_trainer_run(const train_layering_settings *s,
                                        const train_layering_trainer *lt, train_layering_result *r,
                                        nbrdf_error *err);

#endif
