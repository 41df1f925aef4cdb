/* The latent a bundle gives a drawn BRDF, obtained the way a bake obtains it:
 * the base from its table, then the recursive layering network, the innermost
 * coat over the conductor first (coat[0] is the outermost). Held-out
 * evaluation scores these latents; a decoder fine-tune (train decoder
 * --init-bundle) starts its latents from them, in the bundle's latent space. */
#ifndef NBRDF_TRAIN_PARAMS_LATENT_H
#define NBRDF_TRAIN_PARAMS_LATENT_H

#include "nbrdf/model.h"
#include "train/params.h"

/* out: nbrdf_model_latent_dim(m) floats. Parameters outside the tables clamp. */
nbrdf_status train_params_bundle_latent(const nbrdf_model *m, const train_params *p, float *out,
                                        nbrdf_error *err);

#endif
