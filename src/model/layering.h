/* The layering network (paper §4): (latent_top, latent_bottom, A, σT) → the
 * latent of the layered BRDF. One row per colour channel, like the decoder.
 *
 * Input row: [top (D) | bottom (D) | A | log1p(σT)], 2D + 2 floats. σT enters
 * as log(1 + σT): the paper's training values {0, 1, 2, 5} become
 * {0, 0.69, 1.10, 1.79}, comparable in scale to A and to latent entries, and
 * an optically thick slab (σT ≫ 5) saturates instead of driving the first
 * layer far outside its trained range. A enters as it is (in [0, 1]).
 * The output is the latent itself (a plain linear last layer): latents are
 * unconstrained vectors. Three layers = recursive application (the bottom is
 * itself a layered latent).
 *
 * Presets: "paper" width 512, 4 residual blocks (1,098,752 MACs at D = 32),
 * "medium" width 256, 3 blocks (221,696 MACs), "small" width 128, 2 blocks
 * (45,312 MACs).
 * File metadata (besides netio.h's): nbrdf.sigma_t_input = "log1p", nbrdf.preset. */
#ifndef NBRDF_MODEL_LAYERING_H
#define NBRDF_MODEL_LAYERING_H

#include <stddef.h>
#include <stdint.h>

#include "model/netio.h"

typedef struct model_layering {
  char preset[32];
  int latent_dim;
  nn_network *nn; /* 2D + 2 inputs, D outputs */
} model_layering;

extern const char *const model_layering_presets[];

nbrdf_status model_layering_spec(const char *preset, int latent_dim, nn_spec *spec,
                                 nbrdf_error *err);
nbrdf_status model_layering_create(const char *preset, int latent_dim, uint64_t seed,
                                   model_layering **out, nbrdf_error *err);
void model_layering_destroy(model_layering *net);

/* σT as the network sees it. */
float model_layering_sigma_t_input(float sigma_t);

/* Input rows for n layerings: top, bottom [n × D], albedo, sigma_t [n]. */
void model_layering_fill_inputs(const model_layering *net, size_t n, const float *top,
                                const float *bottom, const float *albedo, const float *sigma_t,
                                float *x);

/* out [n × D] (may not alias the inputs); any n (chunked by the runner). */
nbrdf_status model_layering_eval(const model_layering *net, model_runner *runner, size_t n,
                                 const float *top, const float *bottom, const float *albedo,
                                 const float *sigma_t, float *out, nbrdf_error *err);

nbrdf_status model_layering_save(const model_layering *net, const char *path, uint64_t *checksum,
                                 nbrdf_error *err);
nbrdf_status model_layering_read(const nn_st_reader *reader, model_layering **out,
                                 nbrdf_error *err);

#endif
