/* Energy penalty on decoded directional albedo: a latent must not
 * reflect more than its BRDF does.
 *
 *   P = λ · mean over latents l and angles t of max(0, ρ̂_l(θt) − c_l(θt))
 *       (+ max(0, b_l(θt) − ρ̂_l(θt)) where the caller gives floors b)
 *
 * ρ̂ is the decoded albedo by the importance-sampled quadrature of
 * albedo_quad.h with fixed directions per step (drawn from the stream (seed,
 * step), so each step is a pure function of its index and a resumed run is
 * exact). ρ̂ = Σ_k w_k f̂(ωi, ωo_k) is linear in the decoded values, so
 *   ∂P/∂o_k = λ / (n · n_theta) · [ρ̂ > c] · w_k · ∂f̂/∂o_k
 * and the decoder's backward pass carries it into the latents (and the
 * weights). The ceiling c is the caller's: train/energy_reference.h uses
 * min(1, ρ + 2 se + 0.01) from the ground truth, 1 where there is none.
 *
 * The hinge leaves latents below their ceiling alone: it removes created
 * energy (over-bright grazing rims, fireflies) without pulling a fit towards
 * the noisy reference albedo. */
#ifndef NBRDF_MODEL_ENERGY_H
#define NBRDF_MODEL_ENERGY_H

#include <stddef.h>
#include <stdint.h>

#include "model/decoder.h"
#include "nbrdf/status.h"

#define MODEL_ENERGY_MAX_THETA 8

typedef struct model_energy_options {
  float lambda;                             /* penalty weight; 0 = off */
  int n_theta;                              /* 1 .. MODEL_ENERGY_MAX_THETA */
  double theta_deg[MODEL_ENERGY_MAX_THETA]; /* degrees, [0, 90) */
  int samples;                              /* quadrature directions per θi (>= 16) */
  uint64_t seed;
  /* > 0: instead of sampled directions, the polar product rule of albedo_quad.h with
   * polar_rings rings of polar_phi nodes plus the mirror node (samples is then
   * rings × phi + 1), the same every step: the energy audit's rule (bake_audit_rule.h), whose
   * centre node sees a spike at the mirror direction that 128 sampled directions mostly
   * miss (the bake's fine-tune at α 0.001, docs/BAKE.md "Sharp coats"). */
  int polar_rings, polar_phi;
  /* >= 0: the training loops also give each latent a floor, the truth's albedo − 2 se − this
   * margin (train/energy_reference.h), and the penalty adds λ · max(0, floor − ρ̂): a smooth
   * coat over a mirror decoded 0.62 of its light at 85° where the truth keeps 0.98, which the
   * ceiling alone never sees. < 0: off (the hinge above the ceiling only). */
  float floor_margin;
} model_energy_options;

/* λ = 0 (off); θi ∈ {0, 40, 60, 75, 85, 89}°, grazing included; 128 directions each. */
#define MODEL_ENERGY_OPTIONS_DEFAULT                                                               \
  { 0.0f, 6, {0.0, 40.0, 60.0, 75.0, 85.0, 89.0}, 128, 0x656e65726779u, 0, 0, -1.0f }

/* Parses a comma-separated list of angles in degrees into o (message names `option`). */
nbrdf_status model_energy_parse_angles(const char *text, const char *option,
                                       model_energy_options *o, nbrdf_error *err);

typedef struct model_energy model_energy;

/* A penalty for `dec` (borrowed; its weights may change between calls). */
nbrdf_status model_energy_create(const model_decoder *dec, const model_energy_options *o,
                                 model_energy **out, nbrdf_error *err);
void model_energy_destroy(model_energy *e);

/* P of n latents [n × D] against ceilings [n × n_theta] (and floors [n × n_theta], may be
 * NULL: none) with the directions of `step`; *penalty (may be NULL) receives P. ∂P/∂latents is
 * ADDED into grad_latent [n × D] and ∂P/∂weights into grad_weights (each may be NULL: nothing is
 * back-propagated when both are). albedo [n × n_theta] (may be NULL) receives ρ̂. */
nbrdf_status model_energy_add(model_energy *e, size_t n, const float *latents, const float *ceiling,
                              const float *floor, int64_t step, float *grad_latent,
                              float *grad_weights, double *penalty, double *albedo,
                              nbrdf_error *err);

#endif
