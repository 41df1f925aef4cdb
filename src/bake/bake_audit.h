/* Bake-time energy audit: the largest decoded directional albedo
 * over θi of every distinct latent a bake evaluates (the cheap importance-
 * sampled quadrature of model/albedo_quad.h), the worst of the bake with its
 * texel and parameters. A latent above BAKE_AUDIT_LIMIT creates energy: a
 * renderer shows it as an over-bright rim or fireflies. */
#ifndef NBRDF_BAKE_BAKE_AUDIT_H
#define NBRDF_BAKE_BAKE_AUDIT_H

#include <stddef.h>

#include "bake/bake_tuple.h"
#include "model/netio.h"
#include "nbrdf/model.h"

#define BAKE_AUDIT_LIMIT 1.01
/* Angles and directions of the cheap quadrature: 6 × 32 decoder queries per
 * latent. Its maximum over θi is noisy and biased upwards on sharp lobes
 * (measured on α1 0.01, η 1.1, α2 0.3, R0 0.9, A 0.8, σT 0 with the shipped
 * model, 20 seeds: mean 1.32, up to 2.21, against 1.05 ± 0.01 at 16,384
 * directions), so a latent whose cheap maximum exceeds BAKE_AUDIT_REFINE_ABOVE
 * is measured again with 6 × 1,024 (mean 1.053, up to 1.13 there). */
#define BAKE_AUDIT_N_THETA 6
#define BAKE_AUDIT_SAMPLES 32
#define BAKE_AUDIT_REFINE_ABOVE 0.9
#define BAKE_AUDIT_REFINE_SAMPLES 1024
extern const double bake_audit_theta_deg[BAKE_AUDIT_N_THETA];

/* Maximum over bake_audit_theta_deg of the decoded albedo of n latents
 * [n × D] with their proxy sigma [n] (may be NULL): maxv[n], theta_index[n]
 * (may be NULL). Deterministic. Shared with `nbrdf verify`. */
nbrdf_status bake_albedo_max(const nbrdf_model *model, size_t n, const float *latents,
                             const float *sigma, double *maxv, int *theta_index, nbrdf_error *err);

typedef struct bake_audit {
  size_t cap;      /* tuples audited at most (0: off) */
  size_t audited;  /* tuples audited */
  size_t skipped;  /* evaluated tuples left unaudited past the cap */
  size_t over;     /* audited tuples above BAKE_AUDIT_LIMIT */
  double worst;    /* largest maximum albedo; < 0 before any */
  int worst_theta; /* index into bake_audit_theta_deg */
  int x, y, c;     /* a texel (and colour channel) of the worst */
  bake_tuple tuple;
  /* COMPACT (bake_compact.h): the evaluated latents are the bundle's; the audit
   * decodes their compact coordinates with the model it is given. */
  const struct bake_compact *compact;
  /* Optional (borrowed): the audited model's decoder on a GPU (model_gpu.h). */
  struct gpu_network *gpu_decoder;
  /* scratch */
  float *lat, *sigma;
  double *maxv;
  int *theta;
  size_t scratch_cap;
} bake_audit;

void bake_audit_init(bake_audit *a, size_t cap);
void bake_audit_free(bake_audit *a);

/* Audits n distinct tuples: outputs out[idx[k] · (D + 2) ..] (latent, sigma,
 * w). *band_worst (index into the tuples' numbering, or (size_t)-1) and
 * *band_value receive the worst of them when it beats the bake's so far; the
 * caller then names its texel (bake_audit_found). */
nbrdf_status bake_audit_tuples(bake_audit *a, const nbrdf_model *model, const float *out,
                               const size_t *idx, size_t n, size_t *band_worst, nbrdf_error *err);
/* Records the texel (x, y, colour c) and parameters of the new worst. */
void bake_audit_found(bake_audit *a, const bake_tuple *t, int x, int y, int c);

/* The warning text for a bake over the limit (or with unaudited tuples);
 * empty when there is nothing to say. */
void bake_audit_message(const bake_audit *a, int rgb, char *buf, size_t cap);

#endif
