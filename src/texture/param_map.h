/* Parameter maps: images of a BRDF parameter (alpha, eta, R0, A, sigma_t)
 * in any format OpenImageIO reads, delivered as validated floats a band of
 * rows at a time, so that a bake never holds a whole map in memory.
 *
 * Channels: 1 (grey) or 3 (RGB), or either plus alpha: alpha is ignored,
 * and colour under alpha = 0 is read as stored, not multiplied by alpha
 * (oiio_shim.h, NBRDF_IMAGE_UNASSOCIATED_ALPHA); a 4th channel not marked as
 * alpha is ignored too; 5+ channels, or 2 without alpha, are refused. Integer images (8/16-bit)
 * read as [0, 1]. Colour data (R0, A) in integer images is linearised (sRGB by default,
 * ocio_shim.h); float images are taken as linear; non-colour data is never
 * converted. Every texel must end up finite and >= 0. */
#ifndef NBRDF_TEXTURE_PARAM_MAP_H
#define NBRDF_TEXTURE_PARAM_MAP_H

#include "nbrdf/status.h"
#include "texture/oiio_shim.h"

typedef enum texture_param_kind {
  NBRDF_PARAM_DATA = 0,  /* alpha, eta, sigma_t: values used as stored */
  NBRDF_PARAM_COLOUR = 1 /* R0, A: colour data */
} texture_param_kind;

typedef struct texture_param_map_options {
  texture_param_kind kind;
  /* COLOUR only: the map's colour space (ocio_shim.h names). NULL: "srgb"
   * for integer images, "linear" for half/float ones. */
  const char *colour_space;
  const char *ocio_config; /* NULL: $OCIO when set */
  /* Integer images only: map [0, 1] linearly onto [lo, hi], for parameters
   * an 8-bit image cannot hold directly (eta in [1, 2], sigma_t in [0, 5]).
   * Applied after any colour conversion. Float images hold physical values
   * and are never remapped. */
  int remap;
  float lo, hi;
} texture_param_map_options;

#define NBRDF_PARAM_MAP_OPTIONS_DEFAULT                                                            \
  { NBRDF_PARAM_DATA, NULL, NULL, 0, 0.0f, 1.0f }

typedef struct texture_param_map_info {
  int width, height;
  int channels;      /* 1 or 3: floats per texel delivered */
  int file_channels; /* as stored: 1 to 4 */
  texture_pixel_format format;
  int bits_per_sample;
  char format_name[16];           /* "uint8", "half", ... */
  char file_format[32];           /* "png", "openexr", ... */
  char reported_colour_space[64]; /* as OpenImageIO reports it, "" if none */
  char conversion[160];           /* what is applied, for logs and the texture header */
} texture_param_map_info;

typedef struct texture_param_map texture_param_map;

nbrdf_status texture_param_map_open(const char *path, const texture_param_map_options *opts,
                                    texture_param_map **out, nbrdf_error *err);
/* The same for an image in memory (texture_image_open_memory: `data` stays valid until
 * texture_param_map_close; `format` is OpenImageIO's name; `label` names it in messages):
 * for hosts that hold their maps in memory, and for fuzzing without a file per input. */
nbrdf_status texture_param_map_open_memory(const char *label, const char *format,
                                           const void *data, size_t size,
                                           const texture_param_map_options *opts,
                                           texture_param_map **out, nbrdf_error *err);
const texture_param_map_info *texture_param_map_get_info(const texture_param_map *m);
const char *texture_param_map_path(const texture_param_map *m);
/* Rows [y0, y0 + rows): rows * width * channels floats. Fails naming the
 * first NaN, infinite or negative texel ("r0.png: texel (41, 7) is NaN"). */
nbrdf_status texture_param_map_read_rows(texture_param_map *m, int y0, int rows, float *out,
                                         nbrdf_error *err);
void texture_param_map_close(texture_param_map *m);

#endif
