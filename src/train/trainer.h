/* The one training loop every fit runs in (after tiny-cuda-nn's Trainer): it
 * owns the step count, Adam and its learning-rate schedule, progress (rate
 * limited, src/core/progress.h), cancel, the stop limits (a step, minutes),
 * checkpoints (every N seconds at step boundaries the fit allows, on a stop
 * and at the end; written atomically), exact resume, and the run's CSV log.
 * A fit supplies only its loss and gradient for a step, the arrays Adam
 * updates, any other state a resume needs, and hooks for its evaluation and
 * products.
 *
 * Exactness: a fit's gradient of step k must be a function of (its state
 * after step k − 1, k) alone, e.g. its rows drawn from PCG32 stream k, and
 * any generator it carries across steps listed in `state` (restored on
 * resume). Then a run stopped at any step and resumed from its checkpoint
 * reaches the same bytes as one that never stopped.
 *
 * Checkpoint (safetensors): each group's parameters and Adam moments, plain
 * tensors, metadata nbrdf.format, nbrdf.step, nbrdf.options (the settings a
 * resume must share: "key=value" lines; a different value is refused naming
 * the key and both values), nbrdf.state.<name> (integers). */
#ifndef NBRDF_TRAIN_TRAINER_H
#define NBRDF_TRAIN_TRAINER_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include "core/progress.h"
#include "nn/nn.h"
#include "nn/safetensors.h"
#include "train/run_log.h"
#include "train/trainer_parts.h"

typedef struct trainer_options {
  int64_t steps;               /* total steps of the run */
  int64_t stop_at_step;        /* stop (checkpointed) once this many are done; 0 = none */
  double max_seconds;          /* stop (checkpointed) after this long; 0 = no limit */
  const char *checkpoint;      /* NULL: in memory only (no checkpoint, no resume) */
  double checkpoint_seconds;   /* at most this long between checkpoints (<= 0: at every boundary) */
  int64_t checkpoint_boundary; /* time-based checkpoints only after multiples of this (>= 1) */
  const char *format;          /* nbrdf.format of the checkpoint */
  const char *options;         /* nbrdf.options: "key=value\n"... */
  const char *log_path;        /* CSV log (NULL: none); rows start with the step or epoch */
  const char *log_header;
  int64_t log_unit; /* steps per log row number (1, or steps per epoch): kept rows on resume */
  /* Progress: stage, reported as done/total in steps / progress_unit (e.g.
   * epochs), forced at multiples of progress_force and at the end. Either an
   * own ticker from fn/user/cancel, or a borrowed one (ticker != NULL) with
   * an offset (several runs under one bar). */
  const char *stage;
  nbrdf_progress_fn progress;
  void *user;
  volatile sig_atomic_t *cancel;
  core_ticker *ticker;
  double progress_offset, progress_total, progress_unit;
  int64_t progress_force;
} trainer_options;

/* The defaults: in memory, no log, progress in steps. */
#define TRAINER_OPTIONS_DEFAULT                                                                    \
  {                                                                                                \
    0, 0, 0.0, NULL, 300.0, 1, "nbrdf-train-checkpoint", "", NULL, NULL, 1, "train", NULL, NULL,   \
        NULL, NULL, 0.0, 0.0, 1.0, 0                                                               \
  }

typedef struct trainer_result {
  int64_t steps_done, resumed_from;
  int finished;      /* all steps done */
  int legacy_resume; /* resumed from a checkpoint without nbrdf.options */
  double seconds;    /* of this invocation */
} trainer_result;

/* Creates the Adam optimisers, resumes from opts->checkpoint when it exists,
 * runs to opts->steps or a stop, and checkpoints. The arrays are borrowed.
 * Returns NBRDF_ERR_CANCELLED when stopped before the end (by the progress
 * callback, the cancel flag, stop_at_step or max_seconds), after writing the
 * checkpoint when there is one; the message says where and how to resume. */
nbrdf_status trainer_run(const trainer_options *opts, const trainer_fit *fit,
                         const trainer_group *groups, int n_groups, const trainer_tensor *tensors,
                         int n_tensors, const trainer_word *words, int n_words, trainer_result *r,
                         nbrdf_error *err);

/* For the fit's report hook: a log row (printf format, no newline), the
 * seconds since this invocation started, and group g's current learning rate. */
void trainer_log(trainer *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
double trainer_seconds(const trainer *t);
double trainer_lr(const trainer *t, int group);

/* An epoch-based run: `epochs` epochs of `steps_per_epoch` steps; time-based
 * checkpoints and log rows only at epoch boundaries, progress counted in epochs
 * (forced at each epoch's end, ticked between batches so cancel is heard). */
void trainer_options_epochs(trainer_options *to, int epochs, int64_t steps_per_epoch);

/* Step `step` of an epoch-based run over n items in batches of B: the
 * position of its first item in the epoch's order (*first) and the batch's
 * size (B, or what is left at the epoch's end). */
size_t trainer_epoch_batch(int64_t step, int64_t steps_per_epoch, size_t n, size_t B,
                           size_t *first);

/* The shortest text that reads back as x exactly (options compare as text). */
const char *trainer_float_text(float x, char buf[32]);

/* Appends "key=value\n" to an options string of `size` bytes. */
void trainer_option(char *options, size_t size, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif
