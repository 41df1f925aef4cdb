#include "model/autodecoder.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/rng.h"

struct model_fit {
  model_decoder *dec;
  size_t n_brdfs;
  float *latents;
  model_fit_options opts;
  model_runner runner; /* TRAIN mode */
  float *dy, *dx, *target, *row_weight;
  size_t *row_brdf;
  float *grad_latent, *grad_weights; /* grad_weights NULL when the decoder is frozen */
};

void model_fit_destroy(model_fit *fit) {
  if (!fit) return;
  model_runner_destroy(&fit->runner);
  free(fit->dy);
  free(fit->dx);
  free(fit->target);
  free(fit->row_weight);
  free(fit->row_brdf);
  free(fit->grad_latent);
  free(fit->grad_weights);
  free(fit);
}

nbrdf_status model_fit_create(model_decoder *dec, size_t n_brdfs, float *latents,
                              const model_fit_options *opts, model_fit **out, nbrdf_error *err) {
  if (n_brdfs < 1 || opts->rows_per_brdf < 1 || opts->max_batch < 1 || !(opts->lr_latent >= 0.0f) ||
      !(opts->lr_weights >= 0.0f) || !(opts->latent_l2 >= 0.0f))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "fit: needs >= 1 BRDF, rows per BRDF and batch, and non-negative rates");
  model_fit *fit = calloc(1, sizeof *fit);
  if (!fit) return core_fail(err, NBRDF_ERR_MEMORY, "fit: out of memory");
  fit->dec = dec;
  fit->n_brdfs = n_brdfs;
  fit->latents = latents;
  fit->opts = *opts;
  size_t batch = (size_t)opts->max_batch, in = (size_t)model_decoder_inputs(dec);
  size_t n_latent = n_brdfs * (size_t)dec->cfg.latent_dim;
  nbrdf_status st =
      model_runner_create(dec->nn, opts->max_batch, NBRDF_NN_TRAIN, &fit->runner, err);
  if (st != NBRDF_OK) goto fail;
  fit->dy = malloc(batch * sizeof(float));
  fit->dx = malloc(batch * in * sizeof(float));
  fit->target = malloc(batch * sizeof(float));
  fit->row_weight = malloc(batch * sizeof(float));
  fit->row_brdf = malloc(batch * sizeof(size_t));
  fit->grad_latent = malloc(n_latent * sizeof(float));
  if (opts->lr_weights > 0.0f) fit->grad_weights = malloc(nn_param_count(dec->nn) * sizeof(float));
  if (!fit->dy || !fit->dx || !fit->target || !fit->row_weight || !fit->row_brdf ||
      !fit->grad_latent || (opts->lr_weights > 0.0f && !fit->grad_weights)) {
    st = core_fail(err, NBRDF_ERR_MEMORY, "fit: out of memory for %zu latents", n_brdfs);
    goto fail;
  }
  *out = fit;
  return NBRDF_OK;
fail:
  model_fit_destroy(fit);
  return st;
}

/* Fills input row r with BRDF b's latent and the encoding of sample `idx`. */
static void fill_row(model_fit *fit, const model_samples *s, int r, size_t b, size_t idx) {
  size_t dim = (size_t)fit->dec->cfg.latent_dim, in = (size_t)model_decoder_inputs(fit->dec);
  float *row = fit->runner.x + (size_t)r * in;
  memcpy(row, fit->latents + b * dim, dim * sizeof(float));
  model_encode(&fit->dec->cfg.encoding, 1, s->wi + 3 * idx, s->wo + 3 * idx, row + dim, in);
  fit->target[r] = s->f[idx];
  fit->row_weight[r] = s->weight ? s->weight[b] : 1.0f;
  fit->row_brdf[r] = b;
}

/* Forward, loss, backward of the m rows in the runner; gradients accumulate. */
static nbrdf_status run_batch(model_fit *fit, int m, float scale, double *loss, nbrdf_error *err) {
  const model_decoder *dec = fit->dec;
  nbrdf_status st = nn_forward(dec->nn, fit->runner.ws, fit->runner.x, m, fit->runner.y, err);
  if (st != NBRDF_OK) return st;
  *loss += model_loss_sum(fit->opts.loss, dec->cfg.output, (size_t)m, fit->runner.y, fit->target,
                          fit->row_weight, scale, fit->dy);
  st = nn_backward(dec->nn, fit->runner.ws, fit->dy, fit->dx, fit->grad_weights, err);
  if (st != NBRDF_OK) return st;
  size_t dim = (size_t)dec->cfg.latent_dim, in = (size_t)model_decoder_inputs(dec);
  for (int r = 0; r < m; r++) {
    float *g = fit->grad_latent + fit->row_brdf[r] * dim;
    const float *d = fit->dx + (size_t)r * in;
    for (size_t j = 0; j < dim; j++)
      g[j] += d[j];
  }
  return NBRDF_OK;
}

nbrdf_status model_fit_gradient(model_fit *fit, const model_samples *s, int64_t step, double *loss,
                                nbrdf_error *err) {
  if (s->n_brdfs != fit->n_brdfs)
    return core_fail(err, NBRDF_ERR_MISMATCH, "fit: samples for %zu BRDFs, the fit has %zu",
                     s->n_brdfs, fit->n_brdfs);
  size_t dim = (size_t)fit->dec->cfg.latent_dim, n_latent = fit->n_brdfs * dim;
  size_t per = (size_t)fit->opts.rows_per_brdf;
  float scale = (float)(1.0 / ((double)fit->n_brdfs * (double)per));
  memset(fit->grad_latent, 0, n_latent * sizeof(float));
  if (fit->grad_weights) memset(fit->grad_weights, 0, nn_param_count(fit->dec->nn) * sizeof(float));
  core_rng rng;
  core_rng_init(&rng, fit->opts.seed, (uint64_t)step);
  double sum = 0.0;
  int m = 0;
  nbrdf_status st = NBRDF_OK;
  for (size_t b = 0; b < fit->n_brdfs && st == NBRDF_OK; b++) {
    size_t count = s->offsets[b + 1] - s->offsets[b];
    for (size_t j = 0; j < per && st == NBRDF_OK; j++) {
      size_t idx = s->offsets[b] + (size_t)(core_rng_uniform(&rng) * (double)count);
      fill_row(fit, s, m++, b, idx);
      if (m == fit->runner.max_batch) {
        st = run_batch(fit, m, scale, &sum, err);
        m = 0;
      }
    }
  }
  if (st == NBRDF_OK && m > 0) st = run_batch(fit, m, scale, &sum, err);
  if (st != NBRDF_OK) return st;
  double total = sum * (double)scale;
  if (fit->opts.latent_l2 > 0.0f) {
    double lambda = fit->opts.latent_l2 / (double)fit->n_brdfs, prior = 0.0;
    for (size_t k = 0; k < n_latent; k++) {
      prior += (double)fit->latents[k] * fit->latents[k];
      fit->grad_latent[k] += (float)(2.0 * lambda * fit->latents[k]);
    }
    total += lambda * prior;
  }
  if (loss) *loss = total;
  return NBRDF_OK;
}

float *model_fit_grad_latent(model_fit *fit) { return fit->grad_latent; }
float *model_fit_grad_weights(model_fit *fit) { return fit->grad_weights; }
float *model_fit_latents(model_fit *fit) { return fit->latents; }
size_t model_fit_latent_count(const model_fit *fit) {
  return fit->n_brdfs * (size_t)fit->dec->cfg.latent_dim;
}

nbrdf_status model_fit_eval_loss(model_fit *fit, const model_samples *s, double *per_brdf,
                                 double *mean, nbrdf_error *err) {
  if (s->n_brdfs != fit->n_brdfs)
    return core_fail(err, NBRDF_ERR_MISMATCH, "fit: samples for %zu BRDFs, the fit has %zu",
                     s->n_brdfs, fit->n_brdfs);
  const model_decoder *dec = fit->dec;
  double all = 0.0;
  for (size_t b = 0; b < fit->n_brdfs; b++) {
    double sum = 0.0;
    size_t begin = s->offsets[b], end = s->offsets[b + 1];
    for (size_t i0 = begin; i0 < end; i0 += (size_t)fit->runner.max_batch) {
      int m = 0;
      for (size_t i = i0; i < end && m < fit->runner.max_batch; i++)
        fill_row(fit, s, m++, b, i);
      nbrdf_status st = nn_forward(dec->nn, fit->runner.ws, fit->runner.x, m, fit->runner.y, err);
      if (st != NBRDF_OK) return st;
      sum += model_loss_sum(fit->opts.loss, dec->cfg.output, (size_t)m, fit->runner.y, fit->target,
                            NULL, 1.0f, NULL);
    }
    if (per_brdf) per_brdf[b] = sum / (double)(end - begin);
    all += sum;
  }
  if (mean) *mean = all / (double)s->offsets[fit->n_brdfs];
  return NBRDF_OK;
}
