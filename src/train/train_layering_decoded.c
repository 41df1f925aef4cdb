/* The decoded loss of the layering network (train_layering.h): its value
 * over all samples, and its gradient on a batch through the frozen decoder. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/rng.h"
#include "model/encoding.h"
#include "train/energy_reference.h"
#include "train/train_layering.h"

/* Decoder input row r: the latent z and the encoding of sample `idx`. */
static void fill_decoder_row(const model_decoder *dec, const train_samples *data, const float *z,
                             size_t idx, float *row) {
  size_t D = (size_t)dec->cfg.latent_dim, in = (size_t)model_decoder_inputs(dec);
  memcpy(row, z, D * sizeof(float));
  model_encode(&dec->cfg.encoding, 1, data->wi + 3 * idx, data->wo + 3 * idx, row + D, in);
}

/* The latent of pair i: one application, or two for a three-layer pair. */
static nbrdf_status pair_latent(const model_layering *net, model_runner *run,
                                const train_layering_pairs *p, size_t i, float *inner, float *z,
                                nbrdf_error *err) {
  size_t D = (size_t)net->latent_dim;
  if (p->coats[i] != 2)
    return model_layering_eval(net, run, 1, p->top + i * D, p->bottom + i * D, p->albedo + i,
                               p->sigma_t + i, z, err);
  nbrdf_status st = model_layering_eval(net, run, 1, p->mid + i * D, p->bottom + i * D,
                                        p->albedo2 + i, p->sigma_t2 + i, inner, err);
  return st ? st
            : model_layering_eval(net, run, 1, p->top + i * D, inner, p->albedo + i, p->sigma_t + i,
                                  z, err);
}

nbrdf_status train_layering_pair_latents(const model_layering *net, const train_layering_pairs *p,
                                         float *out, nbrdf_error *err) {
  size_t D = (size_t)net->latent_dim;
  model_runner run = {0};
  float *inner = malloc(D * sizeof *inner);
  nbrdf_status st = inner ? model_runner_create(net->nn, 1, NBRDF_NN_INFER, &run, err)
                          : core_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  for (size_t i = 0; i < p->n && !st; i++)
    st = pair_latent(net, &run, p, i, inner, out + i * D, err);
  model_runner_destroy(&run);
  free(inner);
  return st;
}

nbrdf_status train_layering_decoded_loss(const model_layering *net, model_decoder *dec,
                                         model_loss_kind loss, const train_samples *data,
                                         const train_layering_pairs *p, double *mean,
                                         nbrdf_error *err) {
  size_t D = (size_t)dec->cfg.latent_dim, in = (size_t)model_decoder_inputs(dec);
  const int B = 4096;
  model_runner lrun = {0}, drun = {0};
  float *z = malloc(D * sizeof *z), *inner = malloc(D * sizeof *inner);
  float *f = malloc((size_t)B * sizeof *f);
  nbrdf_status st = (z && inner && f)
                        ? NBRDF_OK
                        : core_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  if (!st && net) st = model_runner_create(net->nn, 1, NBRDF_NN_INFER, &lrun, err);
  if (!st) st = model_runner_create(dec->nn, B, NBRDF_NN_INFER, &drun, err);
  double sum = 0.0;
  size_t rows = 0;
  for (size_t i = 0; i < p->n && !st; i++) {
    if (net)
      st = pair_latent(net, &lrun, p, i, inner, z, err);
    else
      memcpy(z, p->target + i * D, D * sizeof *z);
    size_t b = p->brdf[i], begin = data->offsets[b], end = data->offsets[b + 1];
    for (size_t i0 = begin; i0 < end && !st; i0 += (size_t)B) {
      int m = 0;
      for (size_t k = i0; k < end && m < B; k++, m++) {
        fill_decoder_row(dec, data, z, k, drun.x + (size_t)m * in);
        f[m] = data->f[k];
      }
      st = nn_forward(dec->nn, drun.ws, drun.x, m, drun.y, err);
      if (!st) sum += model_loss_sum(loss, dec->cfg.output, (size_t)m, drun.y, f, NULL, 1.0f, NULL);
      rows += (size_t)m;
    }
  }
  *mean = rows ? sum / (double)rows : NAN;
  model_runner_destroy(&lrun);
  model_runner_destroy(&drun);
  free(z), free(inner), free(f);
  return st;
}

/* Decoder rows per forward/backward pass, rounded down to whole pairs (at least one). One pass
 * over a whole batch (128 pairs x 64 rows) kept ~40 MB of buffers out of cache; at 128 rows
 * they stay in L2 and OpenBLAS's SkylakeX kernels take their small-matrix path (see
 * TRAIN_DECODER_GEMM_ROWS in train_decoder.c). */
#define DECODER_PASS_ROWS 128

struct train_layering_decoded {
  model_layering *net;
  model_decoder *dec;
  const train_samples *data;
  int batch, rows;
  int chunk; /* pairs per pass of the decoder */
  model_loss_kind loss;
  uint64_t seed;
  /* TRAIN mode: layering outer and inner (the recursion of three-layer pairs)
   * applications (batch pairs each), decoder (chunk × rows) */
  model_runner lrun, lrun2, drun;
  float *dz, *f, *dy, *dx;
  float *dxl, *dzi; /* outer layering input gradient [batch × (2D+2)], inner's output [batch × D] */
  int *inner_row;   /* batch row of each inner application */
  train_energy *energy; /* NULL: no energy penalty */
};

void train_layering_decoded_destroy(train_layering_decoded *t) {
  if (!t) return;
  train_energy_destroy(t->energy);
  model_runner_destroy(&t->lrun);
  model_runner_destroy(&t->lrun2);
  model_runner_destroy(&t->drun);
  free(t->dz), free(t->f), free(t->dy), free(t->dx), free(t->dxl), free(t->dzi), free(t->inner_row);
  free(t);
}

nbrdf_status train_layering_decoded_create(model_layering *net, model_decoder *dec,
                                           const train_samples *data, int batch, int rows,
                                           model_loss_kind loss, uint64_t seed,
                                           train_layering_decoded **out, nbrdf_error *err) {
  *out = NULL;
  if (batch < 1 || rows < 1 || (int64_t)batch * rows > (1 << 20))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "train layering: batch × rows per pair must be in [1, 2^20] (got %d × %d)",
                     batch, rows);
  if (net->latent_dim != dec->cfg.latent_dim)
    return core_fail(err, NBRDF_ERR_MISMATCH,
                     "train layering: layering latents of %d floats, the decoder's %d",
                     net->latent_dim, dec->cfg.latent_dim);
  train_layering_decoded *t = calloc(1, sizeof *t);
  if (!t) return core_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  t->net = net, t->dec = dec, t->data = data, t->batch = batch, t->rows = rows;
  t->loss = loss, t->seed = seed;
  t->chunk = rows < DECODER_PASS_ROWS ? DECODER_PASS_ROWS / rows : 1;
  if (t->chunk > batch) t->chunk = batch;
  size_t B = (size_t)batch, R = (size_t)rows, D = (size_t)net->latent_dim, C = (size_t)t->chunk;
  nbrdf_status st = model_runner_create(net->nn, batch, NBRDF_NN_TRAIN, &t->lrun, err);
  if (!st) st = model_runner_create(net->nn, batch, NBRDF_NN_TRAIN, &t->lrun2, err);
  if (!st) st = model_runner_create(dec->nn, t->chunk * rows, NBRDF_NN_TRAIN, &t->drun, err);
  if (!st) {
    t->dz = malloc(B * D * sizeof(float));
    t->f = malloc(C * R * sizeof(float));
    t->dy = malloc(C * R * sizeof(float));
    t->dx = malloc(C * R * (size_t)model_decoder_inputs(dec) * sizeof(float));
    t->dxl = malloc(B * (2 * D + 2) * sizeof(float));
    t->dzi = malloc(B * D * sizeof(float));
    t->inner_row = malloc(B * sizeof(int));
    if (!t->dz || !t->f || !t->dy || !t->dx || !t->dxl || !t->dzi || !t->inner_row)
      st = core_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  }
  if (st) {
    train_layering_decoded_destroy(t);
    return st;
  }
  *out = t;
  return NBRDF_OK;
}

nbrdf_status train_layering_decoded_set_energy(train_layering_decoded *t,
                                               const model_energy_options *o, int brdfs_per_batch,
                                               nbrdf_error *err) {
  train_energy_destroy(t->energy);
  t->energy = NULL;
  return train_energy_create(t->dec, t->data, o, brdfs_per_batch, &t->energy, err);
}

nbrdf_status train_layering_decoded_gradient(train_layering_decoded *t,
                                             const train_layering_pairs *p, const size_t *idx,
                                             int m, int64_t step, float *grad, double *loss,
                                             nbrdf_error *err) {
  if (m < 1 || m > t->batch)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "train layering: %d pairs in a batch of %d", m,
                     t->batch);
  const model_decoder *dec = t->dec;
  size_t D = (size_t)dec->cfg.latent_dim, in = (size_t)model_decoder_inputs(dec);
  size_t R = (size_t)t->rows, lin = 2 * D + 2;
  int m2 = 0; /* three-layer pairs: the inner application first */
  for (int r = 0; r < m; r++) {
    size_t i = idx[r];
    if (p->coats[i] != 2) continue;
    model_layering_fill_inputs(t->net, 1, p->mid + i * D, p->bottom + i * D, p->albedo2 + i,
                               p->sigma_t2 + i, t->lrun2.x + (size_t)m2 * lin);
    t->inner_row[m2++] = r;
  }
  nbrdf_status st = NBRDF_OK;
  if (m2) st = nn_forward(t->net->nn, t->lrun2.ws, t->lrun2.x, m2, t->lrun2.y, err);
  if (st) return st;
  for (int r = 0, j = 0; r < m; r++) {
    size_t i = idx[r];
    const float *bottom = p->coats[i] == 2 ? t->lrun2.y + (size_t)j++ * D : p->bottom + i * D;
    model_layering_fill_inputs(t->net, 1, p->top + i * D, bottom, p->albedo + i, p->sigma_t + i,
                               t->lrun.x + (size_t)r * lin);
  }
  st = nn_forward(t->net->nn, t->lrun.ws, t->lrun.x, m, t->lrun.y, err);
  if (st) return st;
  core_rng rng;
  core_rng_init(&rng, t->seed, (uint64_t)step);
  int rows = m * (int)R;
  double sum = 0.0;
  /* The decoder sees the pairs a chunk at a time (its buffers stay in cache); the rows are
   * drawn in the same order as for one pass over all pairs. */
  for (int r0 = 0; r0 < m; r0 += t->chunk) {
    int n = m - r0 < t->chunk ? m - r0 : t->chunk;
    for (int r = 0; r < n; r++) {
      size_t b = p->brdf[idx[r0 + r]], begin = t->data->offsets[b];
      size_t count = t->data->offsets[b + 1] - begin;
      for (size_t j = 0; j < R; j++) {
        size_t k = begin + (size_t)(core_rng_uniform(&rng) * (double)count);
        size_t row = (size_t)r * R + j;
        fill_decoder_row(dec, t->data, t->lrun.y + (size_t)(r0 + r) * D, k, t->drun.x + row * in);
        t->f[row] = t->data->f[k];
      }
    }
    int crows = n * (int)R;
    st = nn_forward(dec->nn, t->drun.ws, t->drun.x, crows, t->drun.y, err);
    if (st) return st;
    sum += model_loss_sum(t->loss, dec->cfg.output, (size_t)crows, t->drun.y, t->f, NULL,
                          (float)(1.0 / rows), t->dy);
    st = nn_backward(dec->nn, t->drun.ws, t->dy, t->dx, NULL, err);
    if (st) return st;
    /* Each pair's latent feeds all its rows: its gradient is their sum. */
    for (int r = 0; r < n; r++) {
      float *g = t->dz + (size_t)(r0 + r) * D;
      memset(g, 0, D * sizeof *g);
      for (size_t j = 0; j < R; j++) {
        const float *d = t->dx + ((size_t)r * R + j) * in;
        for (size_t q = 0; q < D; q++)
          g[q] += d[q];
      }
    }
  }
  *loss = sum / rows;
  double penalty = 0.0;
  st =
      train_energy_pairs(t->energy, (size_t)m, idx, p->brdf, t->lrun.y, step, t->dz, &penalty, err);
  if (st) return st;
  *loss += penalty;
  st = nn_backward(t->net->nn, t->lrun.ws, t->dz, m2 ? t->dxl : NULL, grad, err);
  if (st || !m2) return st;
  /* The inner application's output entered the outer one as its bottom. */
  for (int j = 0; j < m2; j++)
    memcpy(t->dzi + (size_t)j * D, t->dxl + (size_t)t->inner_row[j] * lin + D, D * sizeof(float));
  return nn_backward(t->net->nn, t->lrun2.ws, t->dzi, NULL, grad, err);
}
