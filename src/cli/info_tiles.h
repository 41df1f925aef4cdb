/* `nbrdf info` of a UDIM tile set ('latent.<UDIM>.exr'): a line per tile, then what the
 * tiles share (size, colour mode, storage, model, decoder) or that they differ. */
#ifndef NBRDF_CLI_INFO_TILES_H
#define NBRDF_CLI_INFO_TILES_H

/* The command's exit status: 1 when a tile is unreadable or damaged (the others are still
 * listed), 2 for a bad pattern. */
int info_tiles_run(const char *pattern, int header_only);

#endif
