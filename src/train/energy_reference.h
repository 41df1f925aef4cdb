/* The energy penalty (model/energy.h) in the training loops: the
 * ceilings of the training BRDFs from the ground truth, and the one call each
 * loop makes.
 *
 * Ceiling of BRDF b at θi: min(1, ρ + 2 se + 0.01), ρ and se from
 * nbrdf_brdf_albedo of its parameters (the data set's record), so the penalty
 * fires only where the decoded albedo exceeds the truth by more than its
 * noise and a 1 % margin; 1 where the parameters give no BRDF. With
 * o->floor_margin >= 0 also a floor max(0, ρ − 2 se − margin) (0 without a
 * BRDF): the penalty is then two-sided (model/energy.h). Computed on
 * first use per BRDF (a pure function of the BRDF's index: resumed runs see
 * the same values) and kept for the run.
 *
 * Which latents are penalised: each step, `brdfs_per_step` BRDFs drawn from
 * the stream (seed, step) in the decoder training; the first `brdfs_per_step`
 * pairs of each batch in the layering training. */
#ifndef NBRDF_TRAIN_ENERGY_REFERENCE_H
#define NBRDF_TRAIN_ENERGY_REFERENCE_H

#include <stddef.h>
#include <stdint.h>

#include "model/autodecoder.h"
#include "model/energy.h"
#include "train/samples.h"

/* Reference draws per BRDF and angle (standard error ~1-2 % of ρ). */
#define TRAIN_ENERGY_REF_SAMPLES 2048

typedef struct train_energy train_energy;

/* λ = o->lambda; NULL *out (and NBRDF_OK) when λ = 0: the loops then run as
 * before. `dec` and `data` are borrowed. */
nbrdf_status train_energy_create(const model_decoder *dec, const train_samples *data,
                                 const model_energy_options *o, int brdfs_per_step,
                                 train_energy **out, nbrdf_error *err);
void train_energy_destroy(train_energy *e);

/* Ceilings of n BRDFs (indices into data) at the options' angles, out [n × n_theta]. */
nbrdf_status train_energy_ceilings(train_energy *e, size_t n, const size_t *brdfs, float *out,
                                   nbrdf_error *err);

/* Decoder training: after model_fit_gradient of step `step`, the penalty of
 * the step's BRDFs (drawn from (seed, step), so a resumed run is exact) ADDED
 * into the fit's latent and weight gradients; *penalty its value. e == NULL:
 * nothing (penalty 0). */
nbrdf_status train_energy_add_fit(train_energy *e, model_fit *fit, const float *latents,
                                  int64_t step, double *penalty, nbrdf_error *err);

/* Layering training: the penalty of the first min(m, brdfs_per_step) of m
 * pair latents z [m × D], pair r being BRDF brdf_of[idx[r]]; ∂P/∂z ADDED into
 * dz [m × D] (the decoder frozen). */
nbrdf_status train_energy_pairs(train_energy *e, size_t m, const size_t *idx, const size_t *brdf_of,
                                const float *z, int64_t step, float *dz, double *penalty,
                                nbrdf_error *err);

#endif
