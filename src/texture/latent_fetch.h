/* Latent texture sampling for the renderer: a whole latent texture (every
 * mip level, as floats) in memory, and a trilinear fetch of one texel
 * vector (latents and proxy channels together).
 *
 * Filtering convention (a GLSL shader mirrors it: it is exactly OpenGL's
 * GL_LINEAR_MIPMAP_LINEAR with GL_REPEAT and an explicit lod, textureLod):
 *  - coordinates (u, v) in texture space: u to the right, v DOWN (v = 0 is
 *    the first row of the EXR's data window); the texture repeats with
 *    period 1 in both;
 *  - level l has size max(1, floor(W / 2^l)) x max(1, floor(H / 2^l))
 *    (OpenEXR's round-down mip chain); texel (i, j) of a level of size
 *    (w, h) has its centre at ((i + 0.5) / w, (j + 0.5) / h);
 *  - within a level, bilinear: x = u·w − 0.5, i0 = floor(x), fx = x − i0
 *    (likewise y, j0, fy), the four texels (i0|i0+1 mod w, j0|j0+1 mod h)
 *    weighted (1−fx)(1−fy), fx(1−fy), (1−fx)fy, fx·fy;
 *  - across levels: lod is clamped to [0, levels − 1]; l0 = floor(lod),
 *    t = lod − l0; result = (1 − t)·bilinear(l0) + t·bilinear(l0 + 1)
 *    (level l0 alone when l0 is the last level);
 *  - every channel is filtered the same way, latents (the paper's latent
 *    interpolation, a weighted mean) and the proxy's sigma and w alike;
 *  - the renderer's lod is log2 of the pixel footprint in level-0 texels,
 *    the larger of its u and v extents (camera.h, GL's isotropic rule).
 * Arithmetic is in float, in the order written above. */
#ifndef NBRDF_TEXTURE_LATENT_FETCH_H
#define NBRDF_TEXTURE_LATENT_FETCH_H

#include "nbrdf/model.h"
#include "nbrdf/status.h"
#include "texture/latent_layout.h"

#define TEXTURE_LATENT_MAX_LEVELS 32

typedef struct texture_latent_image {
  texture_latent_layout layout;
  int channels; /* floats per texel, logical order (latent_layout.h) */
  int levels;
  int width[TEXTURE_LATENT_MAX_LEVELS], height[TEXTURE_LATENT_MAX_LEVELS];
  float *data[TEXTURE_LATENT_MAX_LEVELS]; /* level l: width·height·channels floats, row-major */
} texture_latent_image;

/* An image with the round-down chain of `levels` levels of a W x H level 0,
 * data zeroed (tests fill it). */
nbrdf_status texture_latent_image_create(const texture_latent_layout *layout, int width, int height,
                                         int levels, texture_latent_image **out, nbrdf_error *err);
/* Reads every level of the latent texture at `path`. `model_checksum` (may be
 * NULL) receives the bundle checksum recorded in the file, so that a caller
 * can refuse a texture baked with another model. */
nbrdf_status texture_latent_image_load(const char *path, texture_latent_image **out,
                                       char *model_checksum, size_t checksum_size,
                                       nbrdf_error *err);
/* Reads every level of a texture baked with `bundle` (checksum and latent
 * dimension checked) and gives the model that decodes it: `bundle` with the
 * texture's own decoder, if it has one (nbrdf_model_for_texture). */
nbrdf_status texture_latent_image_load_model(const char *path, const nbrdf_model *bundle,
                                             texture_latent_image **out, nbrdf_model **model,
                                             nbrdf_error *err);
void texture_latent_image_free(texture_latent_image *img);

/* The filtered texel at (u, v, lod) into out[channels] (see above). */
void texture_latent_fetch(const texture_latent_image *img, float u, float v, float lod, float *out);
/* Bilinear within one level (lod is not used). */
void texture_latent_fetch_level(const texture_latent_image *img, int level, float u, float v,
                                float *out);

#endif
