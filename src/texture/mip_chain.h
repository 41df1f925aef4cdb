/* Mip chains of latent textures, built while level 0 streams in.
 *
 * Level sizes follow OpenEXR's ROUND_DOWN mip-maps: level l is
 * max(1, floor(W / 2^l)) x max(1, floor(H / 2^l)), and there are
 * floor(log2(max(W, H))) + 1 levels.
 *
 * Filter (paper §4: mip-mapping averages latents): texel (x, y) of level l
 * is the unweighted mean of the level-0 texels in its footprint
 * [x0, x1) x [y0, y1), where x0 = x * 2^l and x1 = (x + 1) * 2^l, except in
 * the last column of a level, whose footprint runs to the edge (x1 = W), and
 * likewise for rows. For sizes that are powers of two this is plain 2x2
 * averaging, level by level. With an odd size, the leftover column of a level
 * joins its neighbour (a 3-wide footprint in the level below), so every
 * level-0 texel contributes to every level, with equal weight within a texel.
 *
 * The builder keeps one row of running sums per level (doubles), so its
 * memory grows with the width of the texture, not its area. */
#ifndef NBRDF_TEXTURE_MIP_CHAIN_H
#define NBRDF_TEXTURE_MIP_CHAIN_H

#include "nbrdf/status.h"

#define NBRDF_MIP_MAX_LEVELS 32

/* Levels of a full ROUND_DOWN chain for a W x H texture (W, H >= 1). */
int texture_mip_level_count(int width, int height);
/* One dimension of level `level`: max(1, floor(dim0 / 2^level)). */
int texture_mip_level_dim(int dim0, int level);
/* The footprint [begin, end) at level 0, along one axis of size dim0, of
 * index i of level `level`. */
void texture_mip_footprint(int dim0, int level, int i, int *begin, int *end);

/* Receives each finished row of each level, top to bottom within a level;
 * row y of level l arrives as soon as its footprint is complete. `row` holds
 * texture_mip_level_dim(width, l) texels of `channels` floats; the callee may
 * modify it (it is the builder's scratch, and is not used again). A non-OK
 * return stops the builder and is passed back to the caller of push_row. */
typedef nbrdf_status (*texture_mip_row_fn)(void *user, int level, int y, float *row,
                                           nbrdf_error *err);

typedef struct texture_mip_builder texture_mip_builder;

/* A builder of `levels` levels (1 .. texture_mip_level_count) for a
 * width x height texture of `channels` floats per texel. */
nbrdf_status texture_mip_builder_create(int width, int height, int channels, int levels,
                                        texture_mip_row_fn emit, void *user,
                                        texture_mip_builder **out, nbrdf_error *err);
/* Feeds the next level-0 row (width * channels floats). Emits it as level 0,
 * then every coarser row it completes. */
nbrdf_status texture_mip_builder_push_row(texture_mip_builder *b, const float *row,
                                          nbrdf_error *err);
/* Level-0 rows pushed so far. */
int texture_mip_builder_rows(const texture_mip_builder *b);
void texture_mip_builder_free(texture_mip_builder *b);

#endif
