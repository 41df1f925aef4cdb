/* The six layered-BRDF parameter inputs on the command line, shared by the
 * commands that take them (`nbrdf bake`, `nbrdf verify`), so that a texture
 * is verified with exactly the options it was baked with. */
#ifndef NBRDF_CLI_PARAMS_H
#define NBRDF_CLI_PARAMS_H

#include <stdio.h>

#include "cli/cli_options.h"
#include "nbrdf/bake.h"

typedef struct cli_params {
  nbrdf_bake_inputs in;
  int given[NBRDF_BAKE_PARAM_COUNT];
  /* 1 where the map is a tile pattern (texture/tile_pattern.h: 'rough.<UDIM>.exr'): its
   * in.param path is then the pattern, a file per tile, and the command works on a set. */
  int tiled[NBRDF_BAKE_PARAM_COUNT];
  nbrdf_roughness roughness;
  int roughness_given;
} cli_params;

/* The bake's defaults: 8/16-bit eta maps span [1, 2], sigma_t maps [0, 5]. */
void cli_params_init(cli_params *p);
/* Readers of the table entries below: a parameter (o->value its id, o->dest the cli_params)
 * and an 8/16-bit map's LO,HI range (o->dest the nbrdf_bake_param). */
int cli_params_read(const char *cmd, const cli_opt *o, const char *value);
int cli_params_read_range(const char *cmd, const cli_opt *o, const char *value);

/* The table entries of the parameter inputs (--alpha1 V ... --sigma-t V, --roughness,
 * --r0-colourspace, --albedo-colourspace, --ocio, --eta-range, --sigma-t-range, --resample),
 * for a command's option table (cli_options.h); `p` a cli_params *. */
// clang-format off
#define CLI_PARAMS_OPTIONS(p)                                                                      \
  CLI_PARAM_OPTION(p, "--alpha1", NBRDF_BAKE_ALPHA1, "top coat roughness (see --roughness)"),      \
  CLI_PARAM_OPTION(p, "--eta", NBRDF_BAKE_ETA, "top coat IOR (8/16-bit maps: see --eta-range)"),   \
  CLI_PARAM_OPTION(p, "--alpha2", NBRDF_BAKE_ALPHA2, "bottom conductor roughness"),                \
  CLI_PARAM_OPTION(p, "--r0", NBRDF_BAKE_R0,                                                       \
                   "bottom Schlick reflectance at normal incidence (colour)"),                     \
  CLI_PARAM_OPTION(p, "--albedo", NBRDF_BAKE_ALBEDO, "slab single-scattering albedo (colour)"),    \
  CLI_PARAM_OPTION(p, "--sigma-t", NBRDF_BAKE_SIGMA_T,                                             \
                   "slab optical depth (8/16-bit maps: see --sigma-t-range)"),                     \
  {.type = CLI_OPT_ENUM, .name = "--roughness", .dest = &(p)->roughness,                           \
   .seen = &(p)->roughness_given, .choices = "alpha|perceptual",                                   \
   .help = "alpha: GGX alpha as in the paper (default); perceptual:\n"                             \
           "the artists' roughness r of Blender et al., alpha = r^2"},                             \
  {.type = CLI_OPT_STRING, .name = "--r0-colourspace", .meta = "CS",                               \
   .dest = &(p)->in.param[NBRDF_BAKE_R0].colour_space,                                             \
   .help = "colour space of 8/16-bit r0 maps (default sRGB)"},                                     \
  {.type = CLI_OPT_STRING, .name = "--albedo-colourspace", .meta = "CS",                           \
   .dest = &(p)->in.param[NBRDF_BAKE_ALBEDO].colour_space,                                         \
   .help = "colour space of 8/16-bit albedo maps (default sRGB)"},                                 \
  {.type = CLI_OPT_PATH, .name = "--ocio", .meta = "CONFIG", .dest = &(p)->in.ocio_config,         \
   .help = "OpenColorIO config for colour spaces (default $OCIO)"},                                \
  {.type = CLI_OPT_CUSTOM, .name = "--eta-range", .meta = "LO,HI",                                 \
   .dest = &(p)->in.param[NBRDF_BAKE_ETA], .parse = cli_params_read_range,                         \
   .help = "8/16-bit eta maps: [0,1] -> [LO,HI] (default 1,2)"},                                   \
  {.type = CLI_OPT_CUSTOM, .name = "--sigma-t-range", .meta = "LO,HI",                             \
   .dest = &(p)->in.param[NBRDF_BAKE_SIGMA_T], .parse = cli_params_read_range,                     \
   .help = "8/16-bit sigma_t maps: [0,1] -> [LO,HI] (default 0,5)"},                               \
  {.type = CLI_OPT_ENUM, .name = "--resample", .dest = &(p)->in.resample,                          \
   .choices = "none|bilinear",                                                                     \
   .help = "maps of different sizes (or not the output size):\n"                                   \
           "an error (default), or each resampled bilinearly to\n"                                 \
           "the output size, else the largest width and height"}
#define CLI_PARAM_OPTION(p, flag, id, text)                                                        \
  {.type = CLI_OPT_CUSTOM, .name = flag, .meta = "V", .dest = (p), .value = (id),                  \
   .seen = &(p)->given[id], .parse = cli_params_read, .help = text}
// clang-format on

/* 1 when any parameter is a tile pattern. */
int cli_params_any_tiled(const cli_params *p);

/* CLI_EXIT_OK when all six parameters were given, else a usage error naming one. */
int cli_params_require(const char *cmd, const cli_params *p);
/* Says a failure of the maps in the options' words: a size mismatch's neutral
 * advice (TEXTURE_RESAMPLE_ADVICE) becomes "pass --resample bilinear". In place,
 * so that the JSON error event says the same. */
void cli_params_explain(nbrdf_error *err);

#endif
