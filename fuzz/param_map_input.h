/* One input of the parameter-map fuzzer: byte 0 chooses the file's extension (bits 0-2), a
 * colour map (bit 3) and an 8-bit remap to [1, 2] (bit 4); the other bytes are the file.
 * fuzz_param_map.c and the corpus replay (tests/texture/test_param_map_corpus.c) both decode
 * inputs here, so a committed corpus file means the same thing to both. */
#ifndef NBRDF_FUZZ_PARAM_MAP_INPUT_H
#define NBRDF_FUZZ_PARAM_MAP_INPUT_H

#include "texture/param_map.h"

/* The extension to give the file; *o gets the map options the tag asks for. */
static inline const char *param_map_input_decode(unsigned char tag, texture_param_map_options *o) {
  static const char *const extensions[8] = {"png", "exr", "tif", "hdr", "tga", "bmp", "ppm", "jpg"};
  texture_param_map_options d = NBRDF_PARAM_MAP_OPTIONS_DEFAULT;
  *o = d;
  if (tag & 8) o->kind = NBRDF_PARAM_COLOUR;
  if (tag & 16) o->remap = 1, o->lo = 1.0f, o->hi = 2.0f;
  return extensions[tag & 7];
}

/* OpenImageIO's name of the reader for extensions[tag & 7], for the in-memory harness. */
static inline const char *param_map_input_format(unsigned char tag) {
  static const char *const formats[8] = {"png",   "openexr", "tiff", "hdr",
                                         "targa", "bmp",     "pnm",  "jpeg"};
  return formats[tag & 7];
}

#endif
