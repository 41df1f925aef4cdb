/* A training run's CSV log (the trainer's, train/trainer.h). Opening a log that already exists (a resumed run)
 * keeps its header and the rows up to the resumed step and drops later ones,
 * which the interrupted run wrote after its last checkpoint and the resumed
 * run repeats; each row is flushed so that the log is readable while the run
 * goes on. */
#ifndef NBRDF_TRAIN_RUN_LOG_H
#define NBRDF_TRAIN_RUN_LOG_H

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>

#include "nbrdf/status.h"

typedef struct train_run_log {
  FILE *f;
} train_run_log;

/* `header` is the first line (without newline); rows start with the step. */
nbrdf_status train_run_log_open(train_run_log *log, const char *path, const char *header,
                                int64_t keep_to_step, nbrdf_error *err);
void train_run_log_row(train_run_log *log, const char *fmt, va_list ap)
    __attribute__((format(printf, 2, 0)));
void train_run_log_close(train_run_log *log);

#endif
