/* Latent textures on disk: one-part, tiled, mip-mapped OpenEXR files
 * written and read through the OpenEXRCore C API. The layout (channel names,
 * attributes, mip filter, compression) is documented in
 * docs/LATENT-TEXTURE.md; channel naming lives in latent_layout.h and the mip
 * filter in mip_chain.h.
 *
 * Handles are not shared between threads while in use; open one reader per
 * thread to read a texture in parallel. */
#ifndef NBRDF_TEXTURE_LATENT_EXR_H
#define NBRDF_TEXTURE_LATENT_EXR_H

#include <stddef.h>
#include <stdint.h>

#include "nbrdf/model.h"
#include "nbrdf/status.h"
#include "texture/latent_layout.h"

typedef enum texture_latent_storage {
  NBRDF_LATENT_HALF = 0, /* 16-bit floats: half the size, ~3 significant digits */
  NBRDF_LATENT_FLOAT = 1 /* 32-bit floats */
} texture_latent_storage;

/* Lossless OpenEXR compressions: ZIP (deflate; ZIPS is the same for tiled
 * files, where every tile is one chunk), PIZ (wavelet + Huffman), RLE.
 * ZIP is the default (docs/LATENT-TEXTURE.md, "Compression"): the smallest
 * half files and the fastest to read; PIZ writes 2-5x faster, makes float
 * files ~20% smaller, but half files ~20-35% larger and float files 3x
 * slower to read. */
typedef enum texture_latent_compression {
  NBRDF_LATENT_ZIP = 0,
  NBRDF_LATENT_PIZ,
  NBRDF_LATENT_ZIPS,
  NBRDF_LATENT_RLE,
  NBRDF_LATENT_NONE
} texture_latent_compression;

/* Called with each finished row of a mip level >= 1 (logical order, texels
 * of the level's width) before it is stored: the bake uses it to recompute
 * the proxy's sigma and w from the averaged latents instead of averaging
 * them. */
typedef nbrdf_status (*texture_latent_mip_row_fn)(void *user, int level, int y, float *row,
                                                  int width, nbrdf_error *err);

typedef struct texture_latent_exr_options {
  texture_latent_storage storage;
  texture_latent_compression compression;
  int tile_size;  /* tile edge in texels, 8..1024, and a tile's bytes at most
                     NBRDF_LATENT_MAX_TILE_BYTES */
  int mip_levels; /* 0: the full chain; 1: level 0 only (OpenEXR's mip-maps are always
                     complete, so no value in between exists) */
  texture_latent_mip_row_fn mip_row; /* optional, see above */
  void *mip_row_user;
  /* Optional: called between groups of tiles being encoded (a row of tiles
   * of a wide texture takes seconds); non-zero stops the writer with
   * NBRDF_ERR_CANCELLED and removes the temporary file. */
  int (*tick)(void *user);
  void *tick_user;
  /* Non-zero: the header gets NBRDF_ATTR_MAX_ALBEDO (latent_layout.h), set by
   * texture_latent_writer_set_max_albedo before finishing. */
  int max_albedo_attr;
} texture_latent_exr_options;

/* Readers refuse bigger tiles, so that a damaged header cannot ask for
 * absurd buffers; the default 64x64 tiles of 102 half channels take 0.8 MiB. */
#define NBRDF_LATENT_MAX_TILE_BYTES (256u << 20)

#define NBRDF_LATENT_EXR_OPTIONS_DEFAULT                                                           \
  { NBRDF_LATENT_HALF, NBRDF_LATENT_ZIP, 64, 0, NULL, NULL, NULL, NULL, 0 }

/* Provenance stored in the header. Strings may be NULL (stored empty). */
typedef struct texture_latent_meta {
  const char *model_name;     /* the model bundle's name */
  const char *model_checksum; /* the bundle's checksum; readers refuse another */
  const char *sources;        /* the six parameter sources, "alpha1=a.png; eta=1.5; ..." */
  const char *settings;       /* bake settings, "key=value; ..." */
  /* Optional: the texture's own decoder, decoder_size bytes of a
   * decoder.safetensors file (at most NBRDF_DECODER_BYTES_MAX); the file is
   * then format version 2. NULL: version 1, no decoder attributes. */
  const void *decoder;
  size_t decoder_size;
  const char *accuracy; /* NBRDF_ATTR_ACCURACY; NULL: not written */
  const char *inputs;   /* NBRDF_ATTR_INPUTS; NULL: not written */
} texture_latent_meta;

const char *texture_latent_compression_name(texture_latent_compression c);
/* "zip", "piz", "zips", "rle", "none"; returns 0 for anything else. */
int texture_latent_compression_parse(const char *name, texture_latent_compression *out);
const char *texture_latent_storage_name(texture_latent_storage s);

/* ---- Writer ----
 * Level-0 texels arrive a band of rows at a time, top to bottom; coarser
 * levels are averaged on the fly and tiles are written as they complete, so
 * memory grows with the texture's width (about 2 * tile_size rows of it),
 * not its area. The file appears at `path` only when texture_latent_writer_finish
 * succeeds. */
typedef struct texture_latent_writer texture_latent_writer;

/* Starts a width x height texture. `inputs` (n_inputs paths, may be NULL)
 * are files the output must not overwrite. `opts` NULL means defaults. */
nbrdf_status texture_latent_writer_create(texture_latent_writer **out, const char *path, int width,
                                          int height, const texture_latent_layout *layout,
                                          const texture_latent_meta *meta,
                                          const texture_latent_exr_options *opts,
                                          const char *const *inputs, int n_inputs,
                                          nbrdf_error *err);
/* Appends `rows` rows of level 0: rows * width texels of
 * texture_latent_channel_count floats each, in logical order. Values must be
 * finite (and within +-65504 for half storage). After any error the
 * temporary file is already gone; release the writer with _abort. */
nbrdf_status texture_latent_writer_write_rows(texture_latent_writer *w, const float *texels,
                                              int rows, nbrdf_error *err);
/* Completes the file and renames it into place; fails if rows are missing.
 * Releases `w` whatever the outcome. */
nbrdf_status texture_latent_writer_finish(texture_latent_writer *w, nbrdf_error *err);
/* The value of NBRDF_ATTR_MAX_ALBEDO (options.max_albedo_attr): the header is
 * written first, so the attribute holds a placeholder (-1) that finish
 * overwrites in place, before the file appears. Ignored without the option. */
void texture_latent_writer_set_max_albedo(texture_latent_writer *w, float value);
/* Cancels: removes the temporary file and releases `w` (NULL is fine). */
void texture_latent_writer_abort(texture_latent_writer *w);

/* ---- Reader ---- */
typedef struct texture_latent_info {
  int format_version;
  int width, height; /* level 0 */
  int levels;        /* mip levels in the file (1 for a single-level texture) */
  int tile_width, tile_height;
  texture_latent_layout layout;
  int channels;                   /* texture_latent_channel_count(&layout) */
  texture_latent_storage storage; /* HALF if any latent channel is half */
  texture_latent_compression compression;
  const char *model_name, *model_checksum; /* never NULL ("" when absent) */
  const char *sources, *settings, *mip_filter, *writer;
  double max_albedo; /* NBRDF_ATTR_MAX_ALBEDO; NaN when absent or not measured */
  const char *accuracy; /* NBRDF_ATTR_ACCURACY, "" when absent (a fast bake) */
  const char *inputs;   /* NBRDF_ATTR_INPUTS, "" when absent */
  int64_t file_size; /* bytes */
  /* Version 2: the size and checksum (16 hex digits, checked at open) of the
   * texture's own decoder (texture_latent_reader_decoder); 0 and "" otherwise. */
  size_t decoder_size;
  const char *decoder_checksum;
} texture_latent_info;

typedef struct texture_latent_reader texture_latent_reader;

/* Opens and validates a latent texture: a single tiled part with mip-map or
 * single-level tiles rounded down, every channel its header declares, a
 * known format version no newer than this build's. Corrupted or truncated
 * files give NBRDF_ERR_FORMAT (or _IO) with the path in the message. */
nbrdf_status texture_latent_reader_open(texture_latent_reader **out, const char *path,
                                        nbrdf_error *err);
const texture_latent_info *texture_latent_reader_info(const texture_latent_reader *r);
/* The path the reader was opened with (for messages). */
const char *texture_latent_reader_path(const texture_latent_reader *r);
/* Size of mip level `level`. */
nbrdf_status texture_latent_reader_level_size(const texture_latent_reader *r, int level, int *width,
                                              int *height, nbrdf_error *err);
/* Reads the rectangle [x, x+w) x [y, y+h) of a level: all channels, texel
 * after texel in logical order (w * h * info.channels floats). */
nbrdf_status texture_latent_reader_read(texture_latent_reader *r, int level, int x, int y, int w,
                                        int h, float *out, nbrdf_error *err);
/* As _read, but only the named channels, in the order given (w * h * n
 * floats). Any channel of the file may be named, nbrdf's or not. */
nbrdf_status texture_latent_reader_read_channels(texture_latent_reader *r, int level, int x, int y,
                                                 int w, int h, const char *const *names, int n,
                                                 float *out, nbrdf_error *err);
void texture_latent_reader_close(texture_latent_reader *r);

/* Reads and decodes every tile of every level and checks that every value
 * of nbrdf's channels is finite: what opening (which reads the header and
 * nothing else) cannot see, a truncated file or a damaged tile, fails here
 * with NBRDF_ERR_FORMAT naming the file, the level and the tile (and the
 * texel and channel of a non-finite value). Costs a full read: about as much
 * as decompressing the file (docs/LATENT-TEXTURE.md, "Checking a file"). */
nbrdf_status texture_latent_reader_check(texture_latent_reader *r, nbrdf_error *err);

/* The bytes of the texture's own decoder (version 2; checksum checked at
 * open), owned by the reader; NULL and *size = 0 when it has none. */
const void *texture_latent_reader_decoder(const texture_latent_reader *r, size_t *size);

/* The model that decodes the open texture: `bundle` with the texture's own
 * decoder, or a new reference to `bundle` (nbrdf_model_for_texture). Checks
 * the model checksum and latent dimension first. */
nbrdf_status texture_latent_reader_model(const texture_latent_reader *r, const nbrdf_model *bundle,
                                         nbrdf_model **out, nbrdf_error *err);

/* Parses the texture's own decoder, if it has one, and checks that it decodes
 * latents of the texture's size: what a reader with a bundle would refuse.
 * `about` (may be NULL) receives a one-line description ("" without one). */
nbrdf_status texture_latent_reader_check_decoder(const texture_latent_reader *r, char *about,
                                                 size_t about_size, nbrdf_error *err);

/* NBRDF_ERR_MISMATCH unless the texture was baked with this model. */
nbrdf_status texture_latent_check_model(const texture_latent_info *info, const char *path,
                                        const char *model_name, const char *model_checksum,
                                        nbrdf_error *err);

#endif
