#include "train/layering_pairs.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"

void train_layering_pairs_free(train_layering_pairs *p) {
  free(p->top), free(p->bottom), free(p->albedo), free(p->sigma_t), free(p->target), free(p->brdf);
  free(p->coats), free(p->mid), free(p->albedo2), free(p->sigma_t2);
  memset(p, 0, sizeof *p);
}

static nbrdf_status pairs_alloc(train_layering_pairs *p, size_t n, size_t D, int targets,
                                nbrdf_error *err) {
  memset(p, 0, sizeof *p);
  p->top = malloc(n * D * sizeof(float));
  p->bottom = malloc(n * D * sizeof(float));
  p->mid = calloc(n * D, sizeof(float));
  p->target = targets ? malloc(n * D * sizeof(float)) : NULL;
  p->albedo = malloc(n * sizeof(float));
  p->sigma_t = malloc(n * sizeof(float));
  p->albedo2 = calloc(n, sizeof(float));
  p->sigma_t2 = calloc(n, sizeof(float));
  p->coats = malloc(n);
  p->brdf = malloc(n * sizeof(size_t));
  if (p->top && p->bottom && p->mid && (p->target || !targets) && p->albedo && p->sigma_t &&
      p->albedo2 && p->sigma_t2 && p->coats && p->brdf)
    return NBRDF_OK;
  train_layering_pairs_free(p);
  return core_fail(err, NBRDF_ERR_MEMORY, "train layering: out of memory for %zu pairs", n);
}

static int held_out(size_t k, int every) {
  return every > 0 && k % (size_t)every == (size_t)every - 1;
}

static nbrdf_status dielectric(const model_base_table *t, const train_coat *c, float *out,
                               nbrdf_error *err) {
  double a = c->alpha, eta = c->eta;
  return model_base_table_lookup(t, 1, &a, &eta, 0, out, NULL, err);
}

nbrdf_status train_layering_pairs_make(const train_samples *data, const float *latents,
                                       const model_base_table t[2], int max_coats, int every,
                                       train_layering_pairs *train, train_layering_pairs *val,
                                       nbrdf_error *err) {
  size_t D = (size_t)t[0].dim, n = 0, nv = 0;
  memset(train, 0, sizeof *train);
  memset(val, 0, sizeof *val);
  for (size_t b = 0; b < data->n_brdfs; b++) {
    int c = data->params[b].n_coats;
    if (c < 1 || c > max_coats) continue;
    nv += (size_t)held_out(n++, every);
  }
  if (n - nv < 1)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "train layering: the data has no layered BRDFs");
  nbrdf_status st = pairs_alloc(train, n - nv, D, latents != NULL, err);
  if (!st) st = pairs_alloc(val, nv ? nv : 1, D, latents != NULL, err);
  if (st) {
    train_layering_pairs_free(train);
    return st;
  }
  size_t k = 0;
  for (size_t b = 0; b < data->n_brdfs && !st; b++) {
    const train_params *p = &data->params[b];
    if (p->n_coats < 1 || p->n_coats > max_coats) continue;
    train_layering_pairs *q = held_out(k++, every) ? val : train;
    size_t i = q->n++;
    double a2 = p->base_alpha, r0 = p->base_r0;
    st = dielectric(&t[0], &p->coat[0], q->top + i * D, err);
    if (!st) st = model_base_table_lookup(&t[1], 1, &a2, &r0, 0, q->bottom + i * D, NULL, err);
    if (!st && p->n_coats == 2) {
      st = dielectric(&t[0], &p->coat[1], q->mid + i * D, err);
      q->albedo2[i] = (float)p->coat[1].albedo;
      q->sigma_t2[i] = (float)p->coat[1].sigma_t;
    }
    q->coats[i] = (unsigned char)p->n_coats;
    q->albedo[i] = (float)p->coat[0].albedo;
    q->sigma_t[i] = (float)p->coat[0].sigma_t;
    q->brdf[i] = b;
    if (latents) memcpy(q->target + i * D, latents + b * D, D * sizeof(float));
  }
  if (st) train_layering_pairs_free(train), train_layering_pairs_free(val);
  return st;
}
