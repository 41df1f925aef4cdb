#include "train/projection.h"

#include <signal.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"

typedef struct projection {
  int n;
  model_fit *fit[TRAIN_PROJECTION_MAX_SETS];
  const model_samples *sets;
  volatile sig_atomic_t *cancel;
} projection;

static nbrdf_status gradient(void *user, int64_t step, double *loss, nbrdf_error *err) {
  projection *p = user;
  double sum = 0.0;
  for (int i = 0; i < p->n; i++) {
    /* A step of both tables is seconds on a loaded machine: Ctrl-C is also seen between
     * the sets, as it was when each table was a run of its own. */
    if (i > 0 && p->cancel && *p->cancel)
      return core_fail(err, NBRDF_ERR_CANCELLED,
                       "projection: cancelled in step %lld (the last checkpoint, if any, "
                       "resumes it)",
                       (long long)step + 1);
    double l = 0.0;
    nbrdf_status st = model_fit_gradient(p->fit[i], &p->sets[i], step, &l, err);
    if (st) return st;
    sum += l;
  }
  *loss = sum;
  return NBRDF_OK;
}

/* The gradient engine's options for p (the decoder frozen: lr_weights 0). */
static model_fit_options fit_options(const train_projection *p) {
  model_fit_options o = MODEL_FIT_OPTIONS_DEFAULT;
  o.loss = p->loss;
  o.rows_per_brdf = p->rows_per_brdf;
  o.lr_latent = p->lr;
  o.seed = p->seed;
  if (p->max_batch > 0) o.max_batch = p->max_batch;
  return o;
}

nbrdf_status train_project_sets(model_decoder *dec, int n_sets, const model_samples *sets,
                                float *const *latents, const train_projection *p,
                                const trainer_options *base, trainer_result *r, nbrdf_error *err) {
  static const char *const names[TRAIN_PROJECTION_MAX_SETS][3] = {
      {"latents.0", "adam.latents.0.m", "adam.latents.0.v"},
      {"latents.1", "adam.latents.1.m", "adam.latents.1.v"},
      {"latents.2", "adam.latents.2.m", "adam.latents.2.v"},
      {"latents.3", "adam.latents.3.m", "adam.latents.3.v"}};
  if (n_sets < 1 || n_sets > TRAIN_PROJECTION_MAX_SETS)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "projection: 1..%d sets", TRAIN_PROJECTION_MAX_SETS);
  projection pr = {.n = n_sets, .sets = sets};
  trainer_group groups[TRAIN_PROJECTION_MAX_SETS];
  model_fit_options o = fit_options(p);
  nbrdf_status st = NBRDF_OK;
  for (int i = 0; i < n_sets && !st; i++) {
    st = model_fit_create(dec, sets[i].n_brdfs, latents[i], &o, &pr.fit[i], err);
    if (st) break;
    groups[i] = (trainer_group){names[i][0],
                                names[i][1],
                                names[i][2],
                                latents[i],
                                model_fit_grad_latent(pr.fit[i]),
                                model_fit_latent_count(pr.fit[i]),
                                p->lr,
                                p->decay_every,
                                p->decay_gamma};
  }
  trainer_options to = TRAINER_OPTIONS_DEFAULT;
  if (base) to = *base;
  pr.cancel = to.cancel;
  char options[2048];
  snprintf(options, sizeof options, "%s", to.options ? to.options : "");
  trainer_option(options, sizeof options, "projection",
                 "loss %s, rows %d, lr %.9g, decay %d x %.9g, seed %llu", model_loss_name(p->loss),
                 p->rows_per_brdf, (double)p->lr, p->decay_every, (double)p->decay_gamma,
                 (unsigned long long)p->seed);
  if (p->max_batch > 0) /* absent at the default: checkpoints from before it still match */
    trainer_option(options, sizeof options, "batch", "%d", p->max_batch);
  for (int i = 0; i < n_sets; i++)
    trainer_option(options, sizeof options, names[i][0], "%zu BRDFs", sets[i].n_brdfs);
  to.options = options;
  to.steps = p->steps;
  trainer_fit fit = {.user = &pr, .gradient = gradient};
  trainer_result own;
  if (!st) st = trainer_run(&to, &fit, groups, n_sets, NULL, 0, NULL, 0, r ? r : &own, err);
  for (int i = 0; i < n_sets; i++)
    model_fit_destroy(pr.fit[i]);
  return st;
}

nbrdf_status train_projection_loss(model_decoder *dec, const model_samples *set, float *latents,
                                   const train_projection *p, double *per_brdf, double *mean,
                                   nbrdf_error *err) {
  model_fit_options o = fit_options(p);
  model_fit *fit = NULL;
  nbrdf_status st = model_fit_create(dec, set->n_brdfs, latents, &o, &fit, err);
  if (!st) st = model_fit_eval_loss(fit, set, per_brdf, mean, err);
  model_fit_destroy(fit);
  return st;
}
