#include "train/trainer.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error.h"
#include "train/checkpoint.h"

#define MAX_GROUPS 8

struct trainer {
  const trainer_options *o;
  const trainer_group *groups;
  int n_groups;
  nn_adam *adam[MAX_GROUPS];
  train_run_log log;
  double t0;
};

void trainer_log(trainer *t, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  train_run_log_row(&t->log, fmt, ap);
  va_end(ap);
}

double trainer_seconds(const trainer *t) { return core_monotonic_seconds() - t->t0; }

double trainer_lr(const trainer *t, int group) {
  return t->adam[group] ? (double)nn_adam_lr(t->adam[group], 0) : 0.0;
}

void trainer_option(char *options, size_t size, const char *key, const char *fmt, ...) {
  size_t at = strlen(options);
  if (at + strlen(key) + 2 >= size) return;
  at += (size_t)snprintf(options + at, size - at, "%s=", key);
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(options + at, size - at, fmt, ap);
  va_end(ap);
  if (n >= 0 && at + (size_t)n + 1 < size) strcat(options + at, "\n");
}

void trainer_options_epochs(trainer_options *to, int epochs, int64_t steps_per_epoch) {
  to->steps = (int64_t)epochs * steps_per_epoch;
  to->checkpoint_boundary = steps_per_epoch;
  to->log_unit = steps_per_epoch;
  to->progress_unit = (double)steps_per_epoch;
  to->progress_force = steps_per_epoch;
}

size_t trainer_epoch_batch(int64_t step, int64_t steps_per_epoch, size_t n, size_t B,
                           size_t *first) {
  size_t k0 = (size_t)(step % steps_per_epoch) * B;
  *first = k0;
  return n - k0 < B ? n - k0 : B;
}

const char *trainer_float_text(float x, char buf[32]) {
  for (int digits = 6; digits <= 9; digits++) {
    snprintf(buf, 32, "%.*g", digits, (double)x);
    if (strtof(buf, NULL) == x) break;
  }
  return buf;
}

static nbrdf_status create_adams(trainer *t, nbrdf_error *err) {
  for (int g = 0; g < t->n_groups; g++) {
    const trainer_group *G = &t->groups[g];
    if (!(G->lr > 0.0f)) continue;
    nn_adam_options ao = NBRDF_ADAM_OPTIONS_DEFAULT;
    ao.lr = G->lr;
    ao.decay_every = G->decay_every;
    ao.decay_gamma = G->decay_gamma;
    nbrdf_status st = nn_adam_create(G->n, &ao, &t->adam[g], err);
    if (st) return st;
  }
  return NBRDF_OK;
}

static nbrdf_status apply(trainer *t, nbrdf_error *err) {
  nbrdf_status st = NBRDF_OK;
  for (int g = 0; g < t->n_groups && !st; g++)
    if (t->adam[g]) st = nn_adam_step(t->adam[g], t->groups[g].params, t->groups[g].grad, err);
  return st;
}

/* The stop message: where the run stopped, and how it resumes. */
static nbrdf_status stopped(const trainer_options *o, int64_t step, nbrdf_error *err) {
  char where[96] = "";
  if (o->progress_force > 1)
    snprintf(where, sizeof where, " (in epoch %lld after batch %lld of %lld)",
             (long long)(step / o->progress_force + 1), (long long)(step % o->progress_force),
             (long long)o->progress_force);
  if (o->progress_force > 1 && step % o->progress_force == 0)
    snprintf(where, sizeof where, " (after epoch %lld)", (long long)(step / o->progress_force));
  return core_fail(err, NBRDF_ERR_CANCELLED, "%s: stopped at step %lld of %lld%s%s", o->stage,
                   (long long)step, (long long)o->steps, where,
                   o->checkpoint ? " (checkpointed; run the same command to resume)" : "");
}

nbrdf_status trainer_run(const trainer_options *o, const trainer_fit *fit,
                         const trainer_group *groups, int n_groups, const trainer_tensor *tensors,
                         int n_tensors, const trainer_word *words, int n_words, trainer_result *r,
                         nbrdf_error *err) {
  memset(r, 0, sizeof *r);
  if (n_groups < 1 || n_groups > MAX_GROUPS || o->steps < 0 || o->checkpoint_boundary < 1 ||
      o->log_unit < 1 || !(o->progress_unit > 0))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: 1..%d parameter groups, steps >= 0", o->stage,
                     MAX_GROUPS);
  trainer t = {.o = o, .groups = groups, .n_groups = n_groups};
  t.t0 = core_monotonic_seconds();
  nbrdf_status st = create_adams(&t, err);
  train_checkpoint_parts parts = {o->format, o->options, groups, t.adam, n_groups,
                                  tensors,   n_tensors,  words,  n_words};
  int64_t step = 0;
  struct stat sb;
  /* No checkpoint yet: start afresh (anything else, a FIFO included, is for
   * the reader to refuse: opening it here could block). */
  if (!st && o->checkpoint && !(stat(o->checkpoint, &sb) != 0 && errno == ENOENT)) {
    st = train_checkpoint_load(o->checkpoint, &parts, fit, &step, &r->legacy_resume, err);
    for (int g = 0; g < n_groups && !st; g++)
      if (t.adam[g]) nn_adam_set_steps(t.adam[g], step);
    r->resumed_from = step;
  }
  if (!st && o->log_path)
    st = train_run_log_open(&t.log, o->log_path, o->log_header, step / o->log_unit, err);
  core_ticker own, *tk = o->ticker ? o->ticker : &own;
  if (!o->ticker) core_ticker_init(&own, o->progress, o->user, o->cancel);
  double total = o->progress_total > 0 ? o->progress_total : (double)o->steps / o->progress_unit;
  double last_ckpt = t.t0;
  /* A stop step the checkpoint already passed stops at once (nothing to save). */
  int stop = o->stop_at_step > 0 && step >= o->stop_at_step;
  while (!st && step < o->steps && !stop) {
    double loss = 0.0;
    st = fit->gradient(fit->user, step, &loss, err);
    if (!st) st = apply(&t, err);
    if (st) break;
    step++;
    double now = core_monotonic_seconds();
    if ((o->stop_at_step > 0 && step >= o->stop_at_step) ||
        (o->max_seconds > 0 && now - t.t0 >= o->max_seconds))
      stop = 1;
    /* A borrowed ticker's owner reports its own first and last (this run is a part). */
    int force = !o->ticker &&
                (step == o->steps || (o->progress_force > 0 && step % o->progress_force == 0));
    if (core_ticker_tick(tk, o->stage, o->progress_offset + (double)step / o->progress_unit, total,
                         force))
      stop = 1;
    int last = stop || step == o->steps;
    int save =
        o->checkpoint &&
        (last || (step % o->checkpoint_boundary == 0 && now - last_ckpt >= o->checkpoint_seconds));
    int flags = (save ? TRAINER_SAVING : 0) | (last ? TRAINER_LAST : 0);
    if (fit->report) st = fit->report(fit->user, &t, step, loss, flags, err);
    if (!st && save) {
      st = train_checkpoint_save(o->checkpoint, &parts, step, err);
      if (!st && fit->save) st = fit->save(fit->user, err);
      last_ckpt = core_monotonic_seconds();
    }
  }
  r->steps_done = step;
  r->finished = !st && step >= o->steps;
  r->seconds = trainer_seconds(&t);
  if (!st && !r->finished) st = stopped(o, step, err);
  train_run_log_close(&t.log);
  for (int g = 0; g < n_groups; g++)
    nn_adam_destroy(t.adam[g]);
  return st;
}
