#include "train/layering_trainer.h"

void train_layering_epoch_loss_add(train_layering_epoch_loss *e, double loss, size_t m) {
  e->sum += loss * (double)m, e->rows += m;
}

int train_layering_epoch_end(train_layering_epoch_loss *e, int64_t done, int64_t steps_per_epoch,
                             double *train_loss) {
  if (done % steps_per_epoch != 0) return 0;
  *train_loss = e->sum / (double)(e->rows ? e->rows : 1);
  e->sum = 0.0, e->rows = 0;
  return (int)(done / steps_per_epoch);
}

nbrdf_status train_layering_trainer_run(const train_layering_settings *s,
                                        const train_layering_trainer *lt, train_layering_result *r,
                                        nbrdf_error *err) {
  trainer_group g = {"layering.params",
                     "adam.m",
                     "adam.v",
                     nn_params(lt->net->nn),
                     lt->grad,
                     nn_param_count(lt->net->nn),
                     s->lr,
                     s->decay_every * (int)lt->steps_per_epoch, /* epochs → steps */
                     s->decay_gamma};
  trainer_options to = TRAINER_OPTIONS_DEFAULT;
  trainer_options_epochs(&to, s->epochs, lt->steps_per_epoch);
  to.stop_at_step = s->stop_at_step, to.max_seconds = s->max_seconds;
  to.checkpoint = s->checkpoint, to.checkpoint_seconds = s->checkpoint_seconds;
  to.format = lt->format, to.options = lt->options;
  to.log_path = s->log_path, to.log_header = lt->log_header;
  /* Ctrl-C (the callback's answer) is heard after every batch, not only at
   * an epoch's end: an epoch of the shipped recipe takes minutes. */
  to.stage = "train layering", to.progress = s->progress, to.user = s->user;
  to.cancel = s->cancel;
  trainer_result tr;
  nbrdf_status st = trainer_run(&to, &lt->fit, &g, 1, NULL, 0, lt->words, lt->n_words, &tr, err);
  r->resumed_from = (int)(tr.resumed_from / lt->steps_per_epoch);
  r->epochs_done = (int)(tr.steps_done / lt->steps_per_epoch);
  r->legacy_resume = tr.legacy_resume;
  return st;
}
