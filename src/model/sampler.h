/* The sampling network (paper §5): latent → (σ, w) of the pdf proxy of Eq. 6
 * (proxy.h). One row per colour channel.
 *
 * Input: the latent only. The paper's issue text reads "(latent, ωi)", but the
 * fitted target is the GNDF averaged over incident directions (Eq. 7–8), so σ
 * and w are per-latent constants: computed once per latent (per texel at bake
 * time, stored next to the latent) instead of once per shading query.
 *
 * Output transform of the two raw outputs (o0, o1):
 *   σ = MODEL_PROXY_SIGMA_MIN + softplus(o0) > 0,   w = sigmoid(o1) ∈ [0, 1].
 * The floor keeps σ = 0 (a delta, pdf = ∞) out of reach of float underflow.
 *
 * Presets: "default" width 64, 2 residual blocks.
 * File metadata (besides netio.h's): nbrdf.sigma_min, nbrdf.preset. */
#ifndef NBRDF_MODEL_SAMPLER_H
#define NBRDF_MODEL_SAMPLER_H

#include <stddef.h>
#include <stdint.h>

#include "model/netio.h"

typedef struct model_sampler {
  char preset[32];
  int latent_dim;
  nn_network *nn; /* D inputs, 2 outputs */
} model_sampler;

extern const char *const model_sampler_presets[];

nbrdf_status model_sampler_spec(const char *preset, int latent_dim, nn_spec *spec,
                                nbrdf_error *err);
nbrdf_status model_sampler_create(const char *preset, int latent_dim, uint64_t seed,
                                  model_sampler **out, nbrdf_error *err);
void model_sampler_destroy(model_sampler *net);

/* The output transform, and its derivatives dσ/do0, dw/do1 (may be NULL). */
void model_sampler_transform(const float o[2], float *sigma, float *w, float *dsigma_do0,
                             float *dw_do1);

/* sigma, w [n]; any n (chunked by the runner). */
nbrdf_status model_sampler_eval(const model_sampler *net, model_runner *runner, size_t n,
                                const float *latents, float *sigma, float *w, nbrdf_error *err);

nbrdf_status model_sampler_save(const model_sampler *net, const char *path, uint64_t *checksum,
                                nbrdf_error *err);
nbrdf_status model_sampler_read(const nn_st_reader *reader, model_sampler **out, nbrdf_error *err);

#endif
