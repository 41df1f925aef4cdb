/* verify's integrity pass: every tile of every level is read (so a damaged
 * tile of a level that the comparison does not sample still fails, with the
 * reader's message naming the file) and every latent checked for being
 * finite. Reading costs far less than decoding: no network runs here. */
#include <math.h>
#include <stdlib.h>

#include "core/error.h"
#include "verify/verify_internal.h"

nbrdf_status verify_scan(texture_latent_reader *r, verify_damage *d, nbrdf_error *err) {
  const texture_latent_info *info = texture_latent_reader_info(r);
  const int tw = info->tile_width, th = info->tile_height, C = info->channels;
  const texture_latent_layout *L = &info->layout;
  d->texels = 0;
  float *buf = malloc(sizeof(float) * (size_t)tw * (size_t)th * (size_t)C);
  if (!buf) return core_fail(err, NBRDF_ERR_MEMORY, "verify: out of memory for a tile");
  nbrdf_status st = NBRDF_OK;
  for (int level = 0; st == NBRDF_OK && level < info->levels; level++) {
    int w, h;
    st = texture_latent_reader_level_size(r, level, &w, &h, err);
    for (int y0 = 0; st == NBRDF_OK && y0 < h; y0 += th)
      for (int x0 = 0; st == NBRDF_OK && x0 < w; x0 += tw) {
        int rw = w - x0 < tw ? w - x0 : tw, rh = h - y0 < th ? h - y0 : th;
        st = texture_latent_reader_read(r, level, x0, y0, rw, rh, buf, err);
        for (int i = 0; st == NBRDF_OK && i < rw * rh; i++) {
          int bad = 0;
          for (int c = 0; c < texture_latent_colours(L) && !bad; c++)
            for (int k = 0; k < L->latent_dim && !bad; k++)
              bad = !isfinite(buf[(size_t)i * C + texture_latent_index_latent(L, c, k)]);
          if (bad && d->texels++ == 0) d->level = level, d->x = x0 + i % rw, d->y = y0 + i / rw;
        }
      }
  }
  free(buf);
  return st;
}
