#include "model/base_table.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

const char *model_table_name(model_table_kind kind) {
  return kind == MODEL_TABLE_DIELECTRIC ? "dielectric" : "conductor";
}

const char *model_table_param(model_table_kind kind, int axis) {
  if (kind == MODEL_TABLE_DIELECTRIC) return axis == 0 ? "alpha1" : "eta";
  return axis == 0 ? "alpha2" : "r0";
}

const char *model_table_axis_tensor(model_table_kind kind, int axis) {
  if (axis == 0) return "alpha";
  return kind == MODEL_TABLE_DIELECTRIC ? "eta" : "r0";
}

void model_base_table_free(model_base_table *t) {
  free(t->axis[0]);
  free(t->axis[1]);
  free(t->latents);
  memset(t, 0, sizeof *t);
}

nbrdf_status model_base_table_init(model_base_table *t, model_table_kind kind, int dim, int n0,
                                   const float *axis0, int n1, const float *axis1,
                                   nbrdf_error *err) {
  memset(t, 0, sizeof *t);
  const int n[2] = {n0, n1};
  const float *axes[2] = {axis0, axis1};
  if (dim < 1 || dim > 4096)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s table: latent dimension %d",
                     model_table_name(kind), dim);
  for (int a = 0; a < 2; a++) {
    if (n[a] < 2 || n[a] > 1 << 16)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "%s table: %d nodes on the %s axis, expected 2..65536",
                       model_table_name(kind), n[a], model_table_param(kind, a));
    for (int i = 0; i < n[a]; i++) {
      if (!isfinite(axes[a][i]) || (i > 0 && !(axes[a][i] > axes[a][i - 1])))
        return core_fail(err, NBRDF_ERR_ARGUMENT,
                         "%s table: the %s axis is not finite and strictly increasing at node %d",
                         model_table_name(kind), model_table_param(kind, a), i);
    }
  }
  t->kind = kind;
  t->dim = dim;
  for (int a = 0; a < 2; a++) {
    t->n[a] = n[a];
    t->axis[a] = malloc((size_t)n[a] * sizeof(float));
  }
  t->latents = calloc((size_t)n0 * (size_t)n1 * (size_t)dim, sizeof(float));
  if (!t->axis[0] || !t->axis[1] || !t->latents) {
    model_base_table_free(t);
    return core_fail(err, NBRDF_ERR_MEMORY, "%s table: out of memory", model_table_name(kind));
  }
  for (int a = 0; a < 2; a++)
    memcpy(t->axis[a], axes[a], (size_t)n[a] * sizeof(float));
  return NBRDF_OK;
}

/* Cell index i (axis[i] <= x <= axis[i+1]) and weight of node i+1, x inside the axis. */
static void locate(const float *axis, int n, double x, int *i, double *t) {
  int lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if ((double)axis[mid] <= x)
      lo = mid;
    else
      hi = mid;
  }
  *i = lo;
  *t = (x - axis[lo]) / ((double)axis[lo + 1] - axis[lo]);
  if (*t < 0.0) *t = 0.0;
  if (*t > 1.0) *t = 1.0;
}

nbrdf_status model_base_table_lookup(const model_base_table *t, size_t n, const double *p0,
                                     const double *p1, int refuse, float *out,
                                     unsigned char *clamped, nbrdf_error *err) {
  size_t dim = (size_t)t->dim;
  for (size_t k = 0; k < n; k++) {
    double p[2] = {p0[k], p1[k]};
    unsigned char flags = 0;
    int cell[2];
    double w[2];
    for (int a = 0; a < 2; a++) {
      double lo = t->axis[a][0], hi = t->axis[a][t->n[a] - 1];
      if (!isfinite(p[a]))
        return core_fail(err, NBRDF_ERR_ARGUMENT, "%s = %g (query %zu) is not finite",
                         model_table_param(t->kind, a), p[a], k);
      if (p[a] < lo || p[a] > hi) {
        if (refuse)
          return core_fail(err, NBRDF_ERR_ARGUMENT,
                           "%s = %g (query %zu) is outside the model's table range [%g, %g]",
                           model_table_param(t->kind, a), p[a], k, lo, hi);
        flags |= (unsigned char)(1u << a);
        p[a] = p[a] < lo ? lo : hi;
      }
      locate(t->axis[a], t->n[a], p[a], &cell[a], &w[a]);
    }
    const float *z00 = t->latents + ((size_t)cell[0] * t->n[1] + cell[1]) * dim;
    const float *z01 = z00 + dim;
    const float *z10 = z00 + (size_t)t->n[1] * dim;
    const float *z11 = z10 + dim;
    double a00 = (1 - w[0]) * (1 - w[1]), a01 = (1 - w[0]) * w[1];
    double a10 = w[0] * (1 - w[1]), a11 = w[0] * w[1];
    float *o = out + k * dim;
    for (size_t j = 0; j < dim; j++)
      o[j] = (float)(a00 * z00[j] + a01 * z01[j] + a10 * z10[j] + a11 * z11[j]);
    if (clamped) clamped[k] = flags;
  }
  return NBRDF_OK;
}

static void tensor_name(char *buf, size_t size, model_table_kind kind, const char *what) {
  snprintf(buf, size, "%s.%s", model_table_name(kind), what);
}

nbrdf_status model_base_table_write(const model_base_table *t, nn_st_writer *w, nbrdf_error *err) {
  char name[64];
  nbrdf_status st = NBRDF_OK;
  for (int a = 0; a < 2 && st == NBRDF_OK; a++) {
    int64_t shape[1] = {t->n[a]};
    tensor_name(name, sizeof name, t->kind, model_table_axis_tensor(t->kind, a));
    st = nn_st_writer_add_borrowed(w, name, 1, shape, t->axis[a], err);
  }
  int64_t shape[3] = {t->n[0], t->n[1], t->dim};
  tensor_name(name, sizeof name, t->kind, "latents");
  if (st == NBRDF_OK) st = nn_st_writer_add_borrowed(w, name, 3, shape, t->latents, err);
  return st;
}

nbrdf_status model_base_table_read(const nn_st_reader *r, model_table_kind kind, int dim,
                                   model_base_table *t, nbrdf_error *err) {
  const char *label = nn_st_label(r);
  char name[64];
  const float *axes[2];
  int n[2];
  for (int a = 0; a < 2; a++) {
    tensor_name(name, sizeof name, kind, model_table_axis_tensor(kind, a));
    const nn_st_tensor *ten = nn_st_find(r, name);
    if (!ten) return core_fail(err, NBRDF_ERR_MISMATCH, "%s: has no tensor '%s'", label, name);
    if (ten->ndim != 1 || ten->shape[0] < 2 || ten->shape[0] > 1 << 16)
      return core_fail(err, NBRDF_ERR_MISMATCH,
                       "%s: tensor '%s' must be a vector of 2..65536 grid nodes", label, name);
    n[a] = (int)ten->shape[0];
    int64_t shape[1] = {n[a]};
    nbrdf_status st = nn_st_expect(r, name, 1, shape, &axes[a], err);
    if (st != NBRDF_OK) return st;
  }
  nbrdf_status st = model_base_table_init(t, kind, dim, n[0], axes[0], n[1], axes[1], err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "%s: ", label);
    return st;
  }
  int64_t shape[3] = {n[0], n[1], dim};
  tensor_name(name, sizeof name, kind, "latents");
  st = nn_st_expect_copy(r, name, 3, shape, t->latents, err);
  if (st != NBRDF_OK) model_base_table_free(t);
  return st;
}
