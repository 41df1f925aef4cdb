#include "texture/param_map.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "texture/ocio_shim.h"

struct texture_param_map {
  char *path;
  texture_image_in *img;
  texture_param_map_info info;
  texture_param_map_options opts;
  texture_colour_xform *xform; /* NULL: no colour conversion */
  int integer;               /* 8/16-bit (or other integer) samples */
  int first_channel;         /* 1 when alpha comes first, else 0 */
};

static int is_integer(texture_pixel_format f, const char *name) {
  if (f == NBRDF_PIXEL_U8 || f == NBRDF_PIXEL_U16) return 1;
  if (f == NBRDF_PIXEL_HALF || f == NBRDF_PIXEL_FLOAT) return 0;
  return strstr(name, "int") != NULL; /* uint32, int16, ... */
}

static nbrdf_status set_up_colour(texture_param_map *m, nbrdf_error *err) {
  texture_param_map_info *in = &m->info;
  if (m->opts.kind != NBRDF_PARAM_COLOUR) {
    snprintf(in->conversion, sizeof in->conversion, "none (non-colour data)");
    return NBRDF_OK;
  }
  const char *space = m->opts.colour_space;
  if (!space) space = m->integer ? "srgb" : "linear";
  nbrdf_status st = texture_colour_xform_create(space, m->opts.ocio_config, &m->xform, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "%s: ", m->path);
    return st;
  }
  snprintf(in->conversion, sizeof in->conversion, "%s", texture_colour_xform_describe(m->xform));
  if (texture_colour_xform_is_identity(m->xform)) {
    texture_colour_xform_free(m->xform);
    m->xform = NULL;
  }
  return NBRDF_OK;
}

/* A map whose image is `img` (NULL: `open_failed` says why): channels, colour, remap. */
static nbrdf_status set_up(texture_param_map *m, nbrdf_status st, const texture_image_info *ii,
                           texture_param_map **out, nbrdf_error *err) {
  const char *path = m->path;
  const texture_param_map_options *opts = &m->opts;
  if (st == NBRDF_OK) {
    texture_param_map_info *in = &m->info;
    in->width = ii->width;
    in->height = ii->height;
    in->file_channels = ii->channels;
    in->format = ii->format;
    in->bits_per_sample = ii->bits_per_sample;
    memcpy(in->format_name, ii->format_name, sizeof in->format_name);
    memcpy(in->file_format, ii->file_format, sizeof in->file_format);
    memcpy(in->reported_colour_space, ii->colour_space, sizeof in->reported_colour_space);
    m->integer = is_integer(ii->format, ii->format_name);
    /* Grey + alpha and RGB + alpha (alpha first or last; a 4th channel not
     * marked as alpha is ignored the same way). */
    int alpha = ii->alpha_channel;
    if (ii->channels == 4 && alpha != 0) alpha = 3;
    if (ii->channels == 1 || ii->channels == 3) {
      in->channels = ii->channels;
    } else if ((ii->channels == 2 || ii->channels == 4) &&
               (alpha == 0 || alpha == ii->channels - 1)) {
      in->channels = ii->channels - 1;
      m->first_channel = alpha == 0 ? 1 : 0;
    } else {
      st = core_fail(err, NBRDF_ERR_UNSUPPORTED,
                     "%s: %d channels; a parameter map has 1 (grey), 3 (RGB), or either plus "
                     "alpha (ignored)",
                     path, ii->channels);
    }
  }
  if (st == NBRDF_OK) st = set_up_colour(m, err);
  if (st == NBRDF_OK && opts->remap && m->integer) {
    size_t len = strlen(m->info.conversion);
    snprintf(m->info.conversion + len, sizeof m->info.conversion - len, "; [0, 1] -> [%g, %g]",
             (double)opts->lo, (double)opts->hi);
  }
  if (st != NBRDF_OK) {
    texture_param_map_close(m);
    return st;
  }
  *out = m;
  return NBRDF_OK;
}

/* A map with no image yet, or NULL with the reason in err. */
static texture_param_map *create(const char *path, const texture_param_map_options **opts,
                                 nbrdf_status *st, nbrdf_error *err) {
  static const texture_param_map_options defaults = NBRDF_PARAM_MAP_OPTIONS_DEFAULT;
  if (!*opts) *opts = &defaults;
  const texture_param_map_options *o = *opts;
  if (o->remap && !(isfinite(o->lo) && isfinite(o->hi) && o->lo >= 0.0f)) {
    *st = core_fail(err, NBRDF_ERR_ARGUMENT, "%s: remap range [%g, %g] is not finite and >= 0",
                    path ? path : "(null)", (double)o->lo, (double)o->hi);
    return NULL;
  }
  texture_param_map *m = calloc(1, sizeof *m);
  if (!m || !path || !(m->path = strdup(path))) {
    free(m);
    *st = core_fail(err, path ? NBRDF_ERR_MEMORY : NBRDF_ERR_ARGUMENT, "%s: cannot open map",
                    path ? path : "(null)");
    return NULL;
  }
  m->opts = *o;
  *st = NBRDF_OK;
  return m;
}

nbrdf_status texture_param_map_open(const char *path, const texture_param_map_options *opts,
                                    texture_param_map **out, nbrdf_error *err) {
  *out = NULL;
  nbrdf_status st;
  texture_param_map *m = create(path, &opts, &st, err);
  if (!m) return st;
  texture_image_info ii;
  /* Alpha is coverage, not a parameter: read the colour as stored (not
   * multiplied by alpha, which zeroes texels under alpha = 0) and drop it. */
  st = texture_image_open(path, NBRDF_IMAGE_UNASSOCIATED_ALPHA, &m->img, &ii, err);
  return set_up(m, st, &ii, out, err);
}

nbrdf_status texture_param_map_open_memory(const char *label, const char *format,
                                           const void *data, size_t size,
                                           const texture_param_map_options *opts,
                                           texture_param_map **out, nbrdf_error *err) {
  *out = NULL;
  nbrdf_status st;
  texture_param_map *m = create(label, &opts, &st, err);
  if (!m) return st;
  texture_image_info ii;
  st = texture_image_open_memory(label, format, data, size, NBRDF_IMAGE_UNASSOCIATED_ALPHA,
                                 &m->img, &ii, err);
  return set_up(m, st, &ii, out, err);
}

const texture_param_map_info *texture_param_map_get_info(const texture_param_map *m) {
  return &m->info;
}

const char *texture_param_map_path(const texture_param_map *m) { return m->path; }

static nbrdf_status validate(const texture_param_map *m, int y0, int rows, const float *v,
                             nbrdf_error *err) {
  int C = m->info.channels, W = m->info.width;
  size_t n = (size_t)rows * W * C;
  for (size_t i = 0; i < n; i++) {
    if (isfinite(v[i]) && v[i] >= 0.0f) continue;
    size_t texel = i / (size_t)C;
    int x = (int)(texel % (size_t)W), y = y0 + (int)(texel / (size_t)W);
    char channel[16] = "";
    if (C == 3) snprintf(channel, sizeof channel, " channel %c", "RGB"[i % 3]);
    const char *what = isnan(v[i]) ? "is NaN" : isinf(v[i]) ? "is infinite" : "is negative";
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: texel (%d, %d)%s %s (%g)%s", m->path, x, y,
                     channel, what, (double)v[i],
                     m->xform && !isnan(v[i]) ? " after colour conversion" : "");
  }
  return NBRDF_OK;
}

nbrdf_status texture_param_map_read_rows(texture_param_map *m, int y0, int rows, float *out,
                                         nbrdf_error *err) {
  const texture_param_map_info *in = &m->info;
  if (y0 < 0 || rows < 1 || rows > in->height - y0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: rows %d..%d of a map %d rows high", m->path, y0,
                     y0 + rows - 1, in->height);
  nbrdf_status st = texture_image_read_rows(m->img, 0, y0, y0 + rows, m->first_channel,
                                            m->first_channel + in->channels, out, err);
  if (st != NBRDF_OK) return st;
  size_t texels = (size_t)rows * in->width;
  if (m->xform && in->channels == 3)
    st = texture_colour_xform_apply_rgb(m->xform, out, texels, err);
  if (m->xform && in->channels == 1)
    st = texture_colour_xform_apply_grey(m->xform, out, texels, err);
  if (st != NBRDF_OK) return st;
  if (m->opts.remap && m->integer) {
    float lo = m->opts.lo, span = m->opts.hi - m->opts.lo;
    for (size_t i = 0; i < texels * in->channels; i++)
      out[i] = lo + out[i] * span;
  }
  return validate(m, y0, rows, out, err);
}

void texture_param_map_close(texture_param_map *m) {
  if (!m) return;
  texture_image_close(m->img);
  texture_colour_xform_free(m->xform);
  free(m->path);
  free(m);
}
