/* The full check of a latent texture (`nbrdf info`): every tile decoded and
 * every value finite. Tiles are read one at a time, so memory is one tile
 * whatever the texture's size. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/error.h"
#include "texture/latent_exr.h"

nbrdf_status texture_latent_reader_check(texture_latent_reader *r, nbrdf_error *err) {
  const texture_latent_info *in = texture_latent_reader_info(r);
  const int T = in->tile_width, U = in->tile_height, C = in->channels;
  float *tile = malloc(sizeof(float) * (size_t)T * (size_t)U * (size_t)C);
  if (!tile)
    return core_fail(err, NBRDF_ERR_MEMORY, "checking a texture: out of memory for a tile");
  nbrdf_status st = NBRDF_OK;
  for (int level = 0; st == NBRDF_OK && level < in->levels; level++) {
    int w = 0, h = 0;
    st = texture_latent_reader_level_size(r, level, &w, &h, err);
    for (int ty = 0; st == NBRDF_OK && ty * U < h; ty++)
      for (int tx = 0; st == NBRDF_OK && tx * T < w; tx++) {
        int x0 = tx * T, y0 = ty * U;
        int tw = w - x0 < T ? w - x0 : T, th = h - y0 < U ? h - y0 : U;
        /* The reader's messages name the file, the level and the tile. */
        st = texture_latent_reader_read(r, level, x0, y0, tw, th, tile, err);
        for (size_t i = 0; st == NBRDF_OK && i < (size_t)tw * th * C; i++) {
          if (isfinite(tile[i])) continue;
          char name[32];
          texture_latent_channel_name(&in->layout, (int)(i % C), name, sizeof name);
          size_t texel = i / C;
          st = core_fail(err, NBRDF_ERR_FORMAT,
                         "%s: tile (%d, %d) of level %d: texel (%d, %d) channel %s is %g "
                         "(a latent texture holds finite values only)",
                         texture_latent_reader_path(r), tx, ty, level, x0 + (int)(texel % tw),
                         y0 + (int)(texel / tw), name, (double)tile[i]);
        }
      }
  }
  free(tile);
  return st;
}
