/* The conventions of the six BRDF parameters that every reader of them shares
 * (bake, `eval --model neural`, verify's ground truth, render's reference mode,
 * the training draws), in one place so that they cannot drift apart:
 * - roughness: the model is trained on GGX alpha; a perceptual roughness r
 *   (nbrdf_roughness, include/nbrdf/bake.h) is alpha = r^2, and textures
 *   record which one they were baked from as roughness=alpha|perceptual in
 *   their settings (docs/LATENT-TEXTURE.md);
 * - sigma_t: trained on the paper's {0, 1, 2, NBRDF_BAKE_SIGMA_T_MAX}; the
 *   maximum is public (bake.h) because the range policy applies above it.
 *   How the layering network sees sigma_t is the network's own business
 *   (model_layering_sigma_t_input, layering.h). */
#ifndef NBRDF_MODEL_PARAM_CONVENTIONS_H
#define NBRDF_MODEL_PARAM_CONVENTIONS_H

#include "nbrdf/bake.h"

/* The GGX alpha of roughness value `r` read under `convention`. In double:
 * for a float r, (float) of the result equals the float product r * r (the
 * double product of two floats is exact), so float callers get the bytes
 * they always had. */
double model_roughness_alpha(nbrdf_roughness convention, double r);

/* "alpha" or "perceptual", as settings strings and command lines spell them. */
const char *model_roughness_name(nbrdf_roughness convention);

/* The convention named `name` ("alpha", "perceptual"); -1 for any other text. */
int model_roughness_parse(const char *name);

#endif
