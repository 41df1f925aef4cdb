#include "train/layering_trainer.h"

#include <string.h>

/* The trainer's view of a layering fit. */
typedef struct layering_run {
  const train_layering_trainer *lt;
  int64_t steps_per_epoch;
  size_t batch;
  double sum; /* loss · pairs of the epoch so far (since the start of this invocation) */
  size_t rows;
  train_layering_result *r;
} layering_run;

int64_t train_layering_steps_per_epoch(const train_layering_settings *s, size_t n) {
  size_t B = (size_t)s->batch;
  return (int64_t)((n + B - 1) / B);
}

/* Batch step % steps_per_epoch of its epoch's shuffle. */
static nbrdf_status gradient(void *user, int64_t step, double *loss, nbrdf_error *err) {
  layering_run *t = user;
  const train_layering_trainer *lt = t->lt;
  const size_t *idx = train_epoch_shuffle_get(lt->shuffle, (uint64_t)(step / t->steps_per_epoch));
  size_t k0, m = trainer_epoch_batch(step, t->steps_per_epoch, lt->n, t->batch, &k0);
  memset(lt->grad, 0, nn_param_count(lt->net->nn) * sizeof *lt->grad);
  nbrdf_status st = lt->batch(lt->user, idx + k0, m, step, loss, err);
  t->sum += *loss * (double)m, t->rows += m;
  return st;
}

static nbrdf_status report(void *user, trainer *tr, int64_t done, double loss, int flags,
                           nbrdf_error *err) {
  (void)loss, (void)flags;
  layering_run *t = user;
  if (done % t->steps_per_epoch != 0) return NBRDF_OK;
  t->r->train_loss = t->sum / (double)(t->rows ? t->rows : 1);
  t->sum = 0.0, t->rows = 0;
  return t->lt->epoch_end(t->lt->user, tr, (int)(done / t->steps_per_epoch), err);
}

static nbrdf_status legacy(void *user, const nn_st_reader *r, int64_t *step, nbrdf_error *err) {
  const layering_run *t = user;
  return t->lt->legacy(t->lt->user, r, step, err);
}

nbrdf_status train_layering_trainer_run(const train_layering_settings *s,
                                        const train_layering_trainer *lt, train_layering_result *r,
                                        nbrdf_error *err) {
  layering_run t = {.lt = lt,
                    .steps_per_epoch = train_layering_steps_per_epoch(s, lt->n),
                    .batch = (size_t)s->batch,
                    .r = r};
  trainer_group g = {"layering.params",
                     "adam.m",
                     "adam.v",
                     nn_params(lt->net->nn),
                     lt->grad,
                     nn_param_count(lt->net->nn),
                     s->lr,
                     s->decay_every * (int)t.steps_per_epoch, /* epochs → steps */
                     s->decay_gamma};
  trainer_options to = TRAINER_OPTIONS_DEFAULT;
  trainer_options_epochs(&to, s->epochs, t.steps_per_epoch);
  to.stop_at_step = s->stop_at_step, to.max_seconds = s->max_seconds;
  to.checkpoint = s->checkpoint, to.checkpoint_seconds = s->checkpoint_seconds;
  to.format = lt->format, to.options = lt->options;
  to.log_path = s->log_path, to.log_header = lt->log_header;
  /* Ctrl-C (the callback's answer) is heard after every batch, not only at
   * an epoch's end: an epoch of the shipped recipe takes minutes. */
  to.stage = "train layering", to.progress = s->progress, to.user = s->user;
  to.cancel = s->cancel;
  trainer_fit fit = {
      .user = &t, .gradient = gradient, .report = report, .legacy = lt->legacy ? legacy : NULL};
  trainer_result tr;
  nbrdf_status st = trainer_run(&to, &fit, &g, 1, NULL, 0, lt->words, lt->n_words, &tr, err);
  r->resumed_from = (int)(tr.resumed_from / t.steps_per_epoch);
  r->epochs_done = (int)(tr.steps_done / t.steps_per_epoch);
  r->legacy_resume = tr.legacy_resume;
  return st;
}
