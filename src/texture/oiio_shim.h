/* A thin C interface to OpenImageIO: read any image it reads into floats,
 * a band of rows at a time, and write simple images. No C++ crosses this
 * header; exceptions are caught and returned as messages. */
#ifndef NBRDF_TEXTURE_OIIO_SHIM_H
#define NBRDF_TEXTURE_OIIO_SHIM_H

#include <stddef.h>

#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#include "core/output_file.h" /* C linkage for the C++ shim too */

/* How samples are stored in a file. Integer formats read as [0, 1]. */
typedef enum texture_pixel_format {
  NBRDF_PIXEL_U8,
  NBRDF_PIXEL_U16,
  NBRDF_PIXEL_HALF,
  NBRDF_PIXEL_FLOAT,
  NBRDF_PIXEL_OTHER /* anything else OIIO reads (uint32, double, ...) */
} texture_pixel_format;

typedef struct texture_image_info {
  int width, height; /* of mip level 0 (the data window) */
  int channels;      /* as stored, alpha included */
  int alpha_channel; /* index of the alpha channel, or -1 */
  int mip_levels;
  texture_pixel_format format;
  int bits_per_sample;   /* 8, 16, 32 ... as reported by OIIO */
  char format_name[16];  /* "uint8", "uint16", "half", "float", ... */
  char file_format[32];  /* OIIO's format name: "png", "openexr", "tiff", ... */
  char colour_space[64]; /* OIIO's "oiio:ColorSpace" ("sRGB", "Linear", ...), or "" */
} texture_image_info;

typedef struct texture_image_in texture_image_in;

/* Flags of texture_image_open. UNASSOCIATED_ALPHA: colour channels as stored in
 * formats that store them unassociated (PNG, TIFF...): OpenImageIO otherwise
 * multiplies them by alpha on read, which turns a parameter map's texels
 * under alpha = 0 into 0. Files that store associated colour (OpenEXR) are
 * read as stored either way. */
enum { NBRDF_IMAGE_UNASSOCIATED_ALPHA = 1 };

/* Refuses anything but a regular file (core/input_file.h) before OpenImageIO
 * sees it. */
nbrdf_status texture_image_open(const char *path, int flags, texture_image_in **out,
                                texture_image_info *info, nbrdf_error *err);
/* The same for an image held in memory (`size` bytes at `data`, which must stay
 * valid until texture_image_close), read by the OpenImageIO reader that
 * `format` names ("png", "openexr", "tiff", ...) without probing others;
 * `label` stands for the file name in messages. Formats whose reader cannot read
 * from memory are refused (NBRDF_ERR_UNSUPPORTED). */
nbrdf_status texture_image_open_memory(const char *label, const char *format, const void *data,
                                       size_t size, int flags, texture_image_in **out,
                                       texture_image_info *info, nbrdf_error *err);
/* The name of channel c ("R", "latent.L00.R", ...). */
const char *texture_image_channel_name(const texture_image_in *img, int c);
/* Size of a mip level; NBRDF_ERR_ARGUMENT if the file has no such level. */
nbrdf_status texture_image_level_size(texture_image_in *img, int level, int *width, int *height,
                                      nbrdf_error *err);
/* Rows [y0, y1) of a mip level (counted from the top of its data window),
 * channels [c0, c1), as floats, texel after texel. */
nbrdf_status texture_image_read_rows(texture_image_in *img, int level, int y0, int y1, int c0,
                                     int c1, float *out, nbrdf_error *err);
void texture_image_close(texture_image_in *img);

/* Writes a width x height image of `channels` (1..16) floats per pixel (1:
 * grey, 3: RGB, 4: RGBA), in the format the file name's extension selects, with
 * samples stored as `format` (integers clamp [0, 1]). The file appears only
 * when complete (temporary file + rename). */
nbrdf_status texture_image_write(const char *path, int width, int height, int channels,
                                 const float *pixels, texture_pixel_format format,
                                 nbrdf_error *err);
/* The same into the open temporary file `f` (its destination's name selects the format),
 * which the caller commits (with a command's other outputs: core_output_file_commit_all)
 * or aborts. */
nbrdf_status texture_image_write_to(core_output_file *f, int width, int height, int channels,
                                    const float *pixels, texture_pixel_format format,
                                    nbrdf_error *err);

const char *texture_pixel_format_name(texture_pixel_format format);

/* On (non-zero): what the image libraries print on stderr themselves while a
 * file is opened or read (libpng prints "libpng error: IDAT: ..." before
 * OpenImageIO returns the same reason) is held back: a failure's message
 * carries it instead, and a success passes it on to stderr unchanged. The
 * CLI turns it on; by default a library leaves the process's stderr alone.
 * Not for programs that write to stderr from other threads meanwhile. */
void texture_image_capture_stderr(int on);

#ifdef __cplusplus
}
#endif
#endif
