/* A parameter source: a constant OR a map (param_map.h). A bake reads every
 * source through the same band view; a constant's view has zero strides, so
 * it costs no memory and no work per texel, and the bake can test
 * texture_param_source_is_constant to hoist it out of its loops entirely. */
#ifndef NBRDF_TEXTURE_PARAM_SOURCE_H
#define NBRDF_TEXTURE_PARAM_SOURCE_H

#include <stddef.h>

#include "nbrdf/status.h"
#include "texture/param_map.h"

typedef struct texture_param_source texture_param_source;

/* A band of rows of a source: texel (x, j) of the band, channel c is
 * data[j * row_stride + x * texel_stride + (channels == 3 ? c : 0)]. */
typedef struct texture_param_band {
  const float *data;
  ptrdiff_t row_stride, texel_stride; /* 0 and 0 for a constant */
  int channels;                       /* 1 or 3 */
} texture_param_band;

static inline float texture_param_band_at(const texture_param_band *b, int x, int j, int c) {
  return b->data[j * b->row_stride + x * b->texel_stride + (b->channels == 3 ? c : 0)];
}

/* A constant of 1 (grey) or 3 (RGB) finite, non-negative values. `name`
 * ("alpha1", "r0", ...) prefixes messages. */
nbrdf_status texture_param_source_constant(const char *name, const float *value, int channels,
                                           texture_param_source **out, nbrdf_error *err);
/* A map read from `path`. */
nbrdf_status texture_param_source_map(const char *name, const char *path,
                                      const texture_param_map_options *opts,
                                      texture_param_source **out, nbrdf_error *err);
/* A command-line argument: "0.3" or "0.8,0.5,0.2" is a constant, anything
 * else a file path (write "./0.5" for a file named like a number). */
nbrdf_status texture_param_source_parse(const char *name, const char *arg,
                                        const texture_param_map_options *opts,
                                        texture_param_source **out, nbrdf_error *err);

int texture_param_source_is_constant(const texture_param_source *s);
int texture_param_source_channels(const texture_param_source *s);
/* Resamples a map bilinearly to width x height (larger or smaller: a
 * point-sampled bilinear, no box filter; texel centres aligned, edges
 * clamped) as it is read; a constant ignores
 * it. The source rows are still validated as read, and a band needs only the
 * source rows under it, so memory still grows with the width. */
nbrdf_status texture_param_source_resample(texture_param_source *s, int width, int height,
                                           nbrdf_error *err);
/* The map's size (after resampling); 0 x 0 for a constant. */
void texture_param_source_size(const texture_param_source *s, int *width, int *height);
/* The constant's value for channel c (0 for a map). */
float texture_param_source_value(const texture_param_source *s, int c);
/* "alpha1=0.3", "r0=0.9,0.6,0.3" or "albedo=maps/a.png (png uint8 rgb, sRGB (built in) ->
 * linear)": for logs and the texture header. */
const char *texture_param_source_describe(const texture_param_source *s);
/* The map behind a source, or NULL for a constant. */
texture_param_map *texture_param_source_get_map(texture_param_source *s);

/* Reads rows [y0, y0 + rows) of the source (a constant ignores them). The
 * band stays valid until the next call or until the source is freed. */
nbrdf_status texture_param_source_read_band(texture_param_source *s, int y0, int rows,
                                            texture_param_band *band, nbrdf_error *err);
void texture_param_source_free(texture_param_source *s);

/* The end of every "maps differ in size" message (NBRDF_ERR_MISMATCH), in
 * the library's neutral words; a caller with its own name for the option
 * replaces it (the CLI: "; pass --resample bilinear ..."). */
#define TEXTURE_RESAMPLE_ADVICE "; maps are resampled to one size only when asked (bilinear)"

/* All maps among `n` sources share one size (constants fit anything); the
 * error names both disagreeing maps. Sets *width, *height to that size, or
 * to 0 x 0 if every source is a constant. */
nbrdf_status texture_param_sources_common_size(texture_param_source *const *sources, int n,
                                               int *width, int *height, nbrdf_error *err);

#endif
