/* One tile of nbrdf_render: what render.c shares with render_tile.c. */
#ifndef NBRDF_RENDER_RENDER_TILE_H
#define NBRDF_RENDER_RENDER_TILE_H

#include <stddef.h>

#include "render/camera.h"
#include "render/env.h"
#include "texture/latent_fetch.h"
#include "nbrdf/render.h"

/* Tiles are fixed (not a function of the thread count), so that network
 * batches, and with them every bit of the image, are the same in any run. */
#define RENDER_TILE 16
/* Pixel samples shaded per network batch (each makes up to 3 queries). */
#define RENDER_BATCH 4096

typedef struct render_ctx {
  const nbrdf_render_options *opts;
  const nbrdf_model *model; /* NEURAL */
  const texture_latent_image *tex;
  const render_env *env;
  render_camera cam;
  int colours; /* output colour channels of the material: 1 or 3 */
} render_ctx;

/* Renders pixels [x0, x0 + w) × [y0, y0 + h) into rgb (the whole image's
 * buffer, width × height × 3); `tile` numbers the tile for random seeds. */
nbrdf_status render_tile(const render_ctx *ctx, int tile, int x0, int y0, int w, int h, float *rgb,
                         size_t *decoded, double *decode_seconds, size_t *brdf_evals,
                         nbrdf_error *err);

#endif
