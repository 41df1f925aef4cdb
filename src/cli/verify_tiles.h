/* `nbrdf verify` of a UDIM tile set ('latent.<UDIM>.exr' against the maps it was baked from,
 * patterns too): the texel sample of one texture spread over the tiles, per-tile and overall
 * figures, in text, progress JSON and --json (docs/VERIFY.md, "Tile sets"). */
#ifndef NBRDF_CLI_VERIFY_TILES_H
#define NBRDF_CLI_VERIFY_TILES_H

#include "cli/cli_params.h"
#include "cli/cli_progress.h"
#include "nbrdf/model.h"
#include "nbrdf/verify.h"

typedef struct verify_tiles_job {
  const cli_params *params;
  const nbrdf_model *model;
  nbrdf_verify_options o; /* o.texels: the whole set's sample per level */
  const char *pattern;    /* the textures */
  const char *json;       /* --json FILE or NULL */
  double max_error;       /* percent, < 0: none */
  const char *gate;       /* "worst", "p90" or "median" (of the whole set) */
  cli_progress_state *ps;
} verify_tiles_job;

/* The command's exit status, as a single texture's verify: 0 verified, 1 over --max-error,
 * damaged or failed (naming the tile), 2 bad usage. */
int verify_tiles_run(verify_tiles_job *job);

#endif
