/* nbrdf_render_write: the linear EXR (OIIO shim, float) and the display PNG
 * (OCIO view transform, then 8 bits). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/output_file.h"
#include "lobe/png_write.h"
#include "render/render_view.h"
#include "nbrdf/render.h"
#include "texture/oiio_shim.h"

static nbrdf_status write_png(core_output_file *f, int width, int height, const float *rgb,
                              const char *display, const char *ocio_config, nbrdf_error *err) {
  size_t n = (size_t)width * height;
  render_view *view = NULL;
  nbrdf_status st = render_view_create(ocio_config, display, NULL, &view, err);
  if (st != NBRDF_OK) return st;
  float *d = malloc(sizeof(float) * 3 * n);
  unsigned char *px = malloc(3 * n);
  if (!d || !px) st = core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", f->path);
  if (st == NBRDF_OK) {
    /* Negative or non-finite radiance has no display value: black. */
    for (size_t i = 0; i < 3 * n; i++)
      d[i] = isfinite(rgb[i]) && rgb[i] > 0.0f ? rgb[i] : 0.0f;
    st = render_view_apply(view, d, n, err);
  }
  if (st == NBRDF_OK) {
    for (size_t i = 0; i < 3 * n; i++) {
      float v = d[i] > 0.0f ? (d[i] < 1.0f ? d[i] : 1.0f) : 0.0f;
      px[i] = (unsigned char)lrintf(v * 255.0f);
    }
    st = lobe_png_write_rgb8_to(f, width, height, px, err);
  }
  free(d), free(px);
  render_view_free(view);
  return st;
}

nbrdf_status nbrdf_render_write(const char *exr_path, const char *png_path, int width, int height,
                                const float *rgb, const char *display, const char *ocio_config,
                                nbrdf_error *err) {
  if (width < 1 || height < 1 || !rgb)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "render write: empty image");
  /* Both files or neither: an EXR without its PNG looks like a finished render. */
  core_output_file files[2];
  int n = 0;
  nbrdf_status st = NBRDF_OK;
  if (exr_path && (st = core_output_file_open(&files[n], exr_path, NULL, 0, err)) == NBRDF_OK) {
    st = texture_image_write_to(&files[n], width, height, 3, rgb, NBRDF_PIXEL_FLOAT, err);
    n++;
  }
  if (st == NBRDF_OK && png_path &&
      (st = core_output_file_open(&files[n], png_path, NULL, 0, err)) == NBRDF_OK) {
    st = write_png(&files[n], width, height, rgb, display, ocio_config, err);
    n++;
  }
  if (st != NBRDF_OK) {
    for (int i = 0; i < n; i++)
      core_output_file_abort(&files[i]);
    return st;
  }
  return core_output_file_commit_all(files, n, err);
}
