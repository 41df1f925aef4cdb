/* `nbrdf bake` of a UDIM tile set (docs/FARM.md, "Tile sets"): maps given as tile patterns
 * ('rough.<UDIM>.exr'), one texture per tile written to the output pattern, each whole or
 * not at all, with per-tile and overall progress, and a resume that skips the tiles whose
 * texture records the same inputs and options (the header's nbrdf:inputs fingerprint). */
#ifndef NBRDF_CLI_BAKE_TILES_H
#define NBRDF_CLI_BAKE_TILES_H

#include "cli/cli_params.h"
#include "cli/cli_progress.h"
#include "nbrdf/bake.h"
#include "nbrdf/model.h"

typedef struct bake_tiles_job {
  const cli_params *params; /* maps: tile patterns, plain files or constants */
  nbrdf_bake_options opts;  /* the command's options; progress and messages are set here */
  const char *out;          /* the output: a tile pattern */
  const char *tiles;        /* --tiles: the tiles to bake ("1001,1003-1005"), NULL: all */
  int force;                /* --force: bake tiles whose texture is up to date too */
  const nbrdf_model *model; /* loaded, with --decoder's decoder when given */
  const char *decoder;      /* --decoder's file (for the fingerprint), or NULL */
  cli_progress_state *ps;
} bake_tiles_job;

/* 1 when the command line asks for a set: a map or the output is a tile pattern, or --tiles
 * or --force was given. */
int bake_tiles_wanted(const cli_params *params, const char *out, const char *tiles, int force);

/* Bakes the set; prints a line (or JSON event) per tile and the set's summary. Returns the
 * command's exit status: 2 for a bad output pattern or tile list, 1 when the maps disagree,
 * a tile fails (the tiles before it stay whole) or Ctrl-C stops it (no half-written file). */
int bake_tiles_run(bake_tiles_job *job);

#endif
