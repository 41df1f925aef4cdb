/* A texture argument that names a UDIM tile set ('latent.<UDIM>.exr'), for the commands that
 * read textures (`nbrdf info`, `nbrdf verify`; docs/FARM.md, "Tile sets"). */
#ifndef NBRDF_CLI_CLI_TILES_H
#define NBRDF_CLI_CLI_TILES_H

#include "texture/tile_set.h"

/* 1 when `arg` is a tile pattern (texture/tile_pattern.h) and no file has that very name. */
int cli_tiles_is_pattern(const char *arg);

/* The tiles of the texture pattern `pattern` found on disk into `set`: CLI_EXIT_OK, or the
 * exit status after a message naming `cmd` (a bad pattern, an unreadable folder, no file). */
int cli_tiles_list(const char *cmd, const char *pattern, texture_tile_set *set);

/* The file of `tile` (malloc'd), or NULL after a message naming `cmd`. */
char *cli_tiles_path(const char *cmd, const char *pattern, int tile);

#endif
