/* Latent look-up tables of the analytic base BRDFs (DESIGN.md "Formats"): the
 * top rough dielectric over a grid of (α1, η) and the bottom rough conductor
 * over a grid of (α2, R0), so that a bake needs no per-texel projection.
 *
 * A table is a grid axis0 × axis1 (each strictly increasing, >= 2 nodes) of
 * latents [n0 × n1 × D]; a query is the bilinear interpolation of the four
 * surrounding latents, linear in the axis values themselves (the axes may be
 * spaced non-uniformly, e.g. denser at small α). Outside the grid a parameter
 * is clamped to the nearest edge and the query flagged, or refused, as the
 * caller chooses; NaN and Inf are always refused.
 *
 * In base_tables.safetensors, table T ∈ {dielectric, conductor} is
 *   T.<axis0>  [n0]      (dielectric.alpha, conductor.alpha)
 *   T.<axis1>  [n1]      (dielectric.eta,   conductor.r0)
 *   T.latents  [n0, n1, D]
 * with metadata nbrdf.format = "nbrdf-base-tables", nbrdf.version = "1",
 * nbrdf.latent_dim. */
#ifndef NBRDF_MODEL_BASE_TABLE_H
#define NBRDF_MODEL_BASE_TABLE_H

#include <stddef.h>
#include <stdint.h>

#include "nn/safetensors.h"

typedef enum model_table_kind {
  MODEL_TABLE_DIELECTRIC = 0,
  MODEL_TABLE_CONDUCTOR = 1
} model_table_kind;

typedef struct model_base_table {
  model_table_kind kind;
  int n[2];
  int dim;
  float *axis[2]; /* n[0], n[1] nodes */
  float *latents; /* [n0 × n1 × dim] */
} model_base_table;

/* "dielectric"/"conductor", and the parameter names of the two axes
 * ("alpha1", "eta" / "alpha2", "r0") and their tensor suffixes ("alpha", "eta" / "alpha", "r0"). */
const char *model_table_name(model_table_kind kind);
const char *model_table_param(model_table_kind kind, int axis);
const char *model_table_axis_tensor(model_table_kind kind, int axis);

/* Allocates a table with the given axes (copied, validated) and zero latents. */
nbrdf_status model_base_table_init(model_base_table *t, model_table_kind kind, int dim, int n0,
                                   const float *axis0, int n1, const float *axis1,
                                   nbrdf_error *err);
void model_base_table_free(model_base_table *t);

/* Bilinear look-up of n queries (p0[k], p1[k]) → out [n × dim]. `refuse`
 * non-zero: an out-of-grid parameter fails with NBRDF_ERR_ARGUMENT naming the
 * parameter, value, range and query index; otherwise it is clamped and
 * clamped[k] (may be NULL) gets bit 0 (axis 0) / bit 1 (axis 1) set. */
nbrdf_status model_base_table_lookup(const model_base_table *t, size_t n, const double *p0,
                                     const double *p1, int refuse, float *out,
                                     unsigned char *clamped, nbrdf_error *err);

/* Adds / reads table `t` to / from a base_tables file. */
nbrdf_status model_base_table_write(const model_base_table *t, nn_st_writer *w, nbrdf_error *err);
nbrdf_status model_base_table_read(const nn_st_reader *r, model_table_kind kind, int dim,
                                   model_base_table *t, nbrdf_error *err);

#endif
