/* verify's error heat-map: one block of pixels per texel of a level, so a
 * user sees where on the material the texture is off. */
#include <math.h>
#include <stdlib.h>

#include "core/error.h"
#include "lobe/png_write.h"
#include "verify/verify_internal.h"
#include "verify/verify_write.h"
#include "texture/mip_chain.h"

/* Dark blue -> yellow -> red for t in [0, 1]. */
static void colour(double t, unsigned char rgb[3]) {
  static const double stops[3][3] = {{0.05, 0.05, 0.35}, {1.0, 0.85, 0.1}, {0.8, 0.0, 0.0}};
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  int i = t < 0.5 ? 0 : 1;
  double f = t < 0.5 ? 2 * t : 2 * t - 1;
  for (int c = 0; c < 3; c++)
    rgb[c] = (unsigned char)lround(255 * (stops[i][c] + f * (stops[i + 1][c] - stops[i][c])));
}

nbrdf_status verify_write_heatmap_to(const nbrdf_verify_report *report, int level, double scale,
                                   core_output_file *f, nbrdf_error *err) {
  const char *path = f->path;
  if (!report || !path || level < 0 || level >= report->levels)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "verify heat-map: no level %d", level);
  const int w = texture_mip_level_dim(report->width, level);
  const int h = texture_mip_level_dim(report->height, level);
  int k = 1;
  while (w * k < 256 && k < 64)
    k++;
  if ((long)w * k * h * k > (1L << 26))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: a %d x %d heat-map is too large", path, w, h);
  if (!(scale > 0)) {
    scale = 0;
    for (size_t i = 0; i < report->n_texels; i++)
      if (report->texels[i].level == level && isfinite(report->texels[i].lobe_error))
        scale = fmax(scale, report->texels[i].lobe_error);
    if (!(scale > 0)) scale = 1;
  }
  const int W = w * k, H = h * k;
  unsigned char *rgb = malloc((size_t)W * H * 3);
  if (!rgb) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  for (size_t i = 0; i < (size_t)W * H * 3; i++)
    rgb[i] = 128; /* not compared */
  for (size_t i = 0; i < report->n_texels; i++) {
    const nbrdf_verify_texel *t = &report->texels[i];
    if (t->level != level) continue;
    unsigned char c[3] = {255, 255, 255}; /* a damaged (non-finite) texel */
    if (isfinite(t->lobe_error)) colour(t->lobe_error / scale, c);
    for (int y = t->y * k; y < (t->y + 1) * k; y++)
      for (int x = t->x * k; x < (t->x + 1) * k; x++)
        for (int j = 0; j < 3; j++)
          rgb[((size_t)y * W + x) * 3 + j] = c[j];
  }
  nbrdf_status st = lobe_png_write_rgb8_to(f, W, H, rgb, err);
  free(rgb);
  return st;
}

nbrdf_status nbrdf_verify_write_heatmap(const nbrdf_verify_report *report, int level, double scale,
                                        const char *path, nbrdf_error *err) {
  core_output_file f;
  nbrdf_status st = core_output_file_open(&f, path, NULL, 0, err);
  if (st != NBRDF_OK) return st;
  st = verify_write_heatmap_to(report, level, scale, &f, err);
  if (st != NBRDF_OK) {
    core_output_file_abort(&f);
    return st;
  }
  return core_output_file_commit(&f, err);
}
