#include "lobe/lobe_png.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "lobe/lobe.h"
#include "lobe/png_write.h"

enum { GAP = 4 }; /* pixels of background between panels */

/* Viridis (van der Walt & Smith, matplotlib) at five stops, linearly interpolated. */
static void viridis(double v, unsigned char *rgb) {
  static const double stops[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  v = v < 0 ? 0 : v > 1 ? 1 : v;
  double s = v * 4.0;
  int i = s >= 4.0 ? 3 : (int)s;
  double t = s - i;
  for (int c = 0; c < 3; c++)
    rgb[c] = (unsigned char)lround(stops[i][c] + t * (stops[i + 1][c] - stops[i][c]));
}

/* Signed difference: black at 0, red above, blue below. */
static void diverging(double d, unsigned char *rgb) {
  double m = pow(fmin(fabs(d), 1.0), 1.0 / 2.2);
  unsigned char hi = (unsigned char)lround(255 * m), lo = (unsigned char)lround(64 * m);
  rgb[0] = d > 0 ? hi : lo;
  rgb[1] = lo;
  rgb[2] = d > 0 ? lo : hi;
}

nbrdf_status lobe_write_png(const char *path, int res, int n_images, const double *ref,
                            const double *approx, int zoom, nbrdf_error *err) {
  if (res < 1 || res > 1024 || n_images < 1 || n_images > 64 || zoom < 1 || zoom > 16)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s: lobe PNG of %d images of %d² pixels at zoom %d is out of range", path,
                     n_images, res, zoom);
  const int cols = approx ? 3 : 1, panel = res * zoom;
  const int width = cols * panel + (cols + 1) * GAP,
            height = n_images * panel + (n_images + 1) * GAP;
  unsigned char *rgb = malloc((size_t)width * (size_t)height * 3);
  if (!rgb) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  memset(rgb, 255, (size_t)width * (size_t)height * 3);
  const size_t stride = (size_t)res * (size_t)res;
  for (int t = 0; t < n_images; t++) {
    const double *r = ref + (size_t)t * stride, *a = approx ? approx + (size_t)t * stride : NULL;
    double peak = 0.0;
    for (size_t p = 0; p < stride; p++)
      peak = fmax(peak, r[p]);
    const double scale = peak > 0.0 ? 1.0 / peak : 1.0;
    for (int c = 0; c < cols; c++)
      for (int row = 0; row < res; row++)
        for (int col = 0; col < res; col++) {
          double wo[3];
          size_t p = (size_t)row * (size_t)res + (size_t)col;
          unsigned char px[3] = {0, 0, 0}; /* outside the disk */
          if (lobe_pixel_wo(res, row, col, wo)) {
            if (c == 2)
              diverging((a[p] - r[p]) * scale, px);
            else
              viridis(pow(fmax((c == 0 ? r[p] : a[p]) * scale, 0.0), 1.0 / 2.2), px);
          }
          for (int dy = 0; dy < zoom; dy++) {
            int y = GAP + t * (panel + GAP) + row * zoom + dy;
            unsigned char *dst =
                rgb +
                ((size_t)y * (size_t)width + (size_t)(GAP + c * (panel + GAP) + col * zoom)) * 3;
            for (int dx = 0; dx < zoom; dx++)
              memcpy(dst + 3 * dx, px, 3);
          }
        }
  }
  nbrdf_status st = lobe_png_write_rgb8(path, width, height, rgb, err);
  free(rgb);
  return st;
}
