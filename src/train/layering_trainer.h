/* What the two layering fits share of the trainer (train/trainer.h): the
 * latent loss (train_layering.c) and the decoded loss
 * (train_layering_decoded_fit.c) each supply their step's loss, their
 * epoch-end evaluation and their checkpoint's identity; this holds the rest
 * once: the layering network's Adam group with the settings' schedule
 * (decay counted in epochs), the settings' epochs, limits, checkpoint,
 * progress and cancel, and the train loss of an epoch. */
#ifndef NBRDF_TRAIN_LAYERING_TRAINER_H
#define NBRDF_TRAIN_LAYERING_TRAINER_H

#include <stddef.h>
#include <stdint.h>

#include "train/train_layering.h"
#include "train/trainer.h"

/* The train loss of the epoch in progress: loss · rows so far (since the
 * start of this invocation). */
typedef struct train_layering_epoch_loss {
  double sum;
  size_t rows;
} train_layering_epoch_loss;

/* Adds a batch of m rows with mean loss `loss`. */
void train_layering_epoch_loss_add(train_layering_epoch_loss *e, double loss, size_t m);
/* For a report hook after `done` steps: at an epoch's end, the epoch's mean
 * loss into *train_loss, the sum restarted, and the epoch's number (>= 1);
 * else 0 and nothing changed. */
int train_layering_epoch_end(train_layering_epoch_loss *e, int64_t done, int64_t steps_per_epoch,
                             double *train_loss);

/* What a layering fit gives its run besides the settings. */
typedef struct train_layering_trainer {
  model_layering *net;
  const float *grad; /* the net's gradient, filled by fit.gradient */
  int64_t steps_per_epoch;
  const char *format;     /* nbrdf.format of the checkpoint */
  const char *options;    /* nbrdf.options: what a resume must share */
  const char *log_header; /* the CSV log's header (rows: trainer_log in fit.report) */
  trainer_fit fit;
  const trainer_word *words; /* further state a resume needs (may be NULL) */
  int n_words;
} train_layering_trainer;

/* Runs the fit under s (trainer_run's contract) and fills r's resumed_from,
 * epochs_done and legacy_resume. */
nbrdf_status train_layering_trainer_run(const train_layering_settings *s,
                                        const train_layering_trainer *lt, train_layering_result *r,
                                        nbrdf_error *err);

#endif
