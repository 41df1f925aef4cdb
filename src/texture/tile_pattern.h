/* UDIM tile patterns: one path that names a file per tile of a tile set.
 *
 * A tile is numbered as UDIM does: 1001 + u + 10 v, for the unit square
 * [u, u + 1) x [v, v + 1) of texture space. nbrdf handles u 0..9 and v 0..9,
 * tiles 1001..1100 (up to 100 tiles per set).
 *
 * The tokens, as OpenImageIO's texture system expands them (its "UDIM texture
 * atlases"), plus Mudbox's and Blender's <UVTILE>:
 *   <UDIM>, %(UDIM)d   1001 + u + 10 v        rough.<UDIM>.exr   -> rough.1003.exr
 *   <u> ... <v>        u, v (0-based)          rough_u<u>_v<v>.exr -> rough_u2_v0.exr
 *   <U> ... <V>        u + 1, v + 1 (1-based)  rough_u<U>_v<V>.exr -> rough_u3_v1.exr
 *   <UVTILE>, <uvtile> u<u+1>_v<v+1>           rough.<UVTILE>.exr -> rough.u3_v1.exr
 * Numbers have no leading zeros (OIIO prints them with %d). Not supported:
 * OIIO's _u##v## and Houdini's %(U)02d forms (the padding is not in the
 * token), Arnold's <tile>, V-Ray's $U/$V.
 *
 * A pattern names its tile once: one of <UDIM>, %(UDIM)d, <UVTILE>, or a u
 * token and a v token of one convention (<u> with <v>, <U> with <V>), in
 * the file name (not in a folder). A digit right after a token is refused
 * (where would the number end?). A path with no token is a plain path: the
 * same file for every tile. */
#ifndef NBRDF_TEXTURE_TILE_PATTERN_H
#define NBRDF_TEXTURE_TILE_PATTERN_H

#include <stddef.h>

#include "nbrdf/status.h"

#define TEXTURE_TILE_FIRST 1001
#define TEXTURE_TILE_LAST 1100
#define TEXTURE_TILE_COUNT (TEXTURE_TILE_LAST - TEXTURE_TILE_FIRST + 1)

/* The tile's place in texture space: it covers [u, u + 1) x [v, v + 1).
 * `tile` must be valid (texture_tile_check). */
void texture_tile_uv(int tile, int *u, int *v);
/* The tile at (u, v), or 0 outside u 0..9, v 0..9. */
int texture_tile_at(int u, int v);
/* NBRDF_ERR_ARGUMENT naming `tile` unless it is in 1001..1100. */
nbrdf_status texture_tile_check(int tile, nbrdf_error *err);
/* A tile number written in decimal ("1003"), for options such as --tile. */
nbrdf_status texture_tile_parse(const char *text, int *tile, nbrdf_error *err);

typedef struct texture_tile_pattern texture_tile_pattern;

/* Parses `path` (a tile pattern or a plain path). Bad patterns (two tile
 * tokens, a u token without a v token, an unknown <token>, a token in a
 * folder, a digit right after a token) are NBRDF_ERR_ARGUMENT, the message
 * quoting the path. */
nbrdf_status texture_tile_pattern_parse(const char *path, texture_tile_pattern **out,
                                        nbrdf_error *err);
void texture_tile_pattern_free(texture_tile_pattern *p);

/* 1 when the path holds a tile token, 0 for a plain path. */
int texture_tile_pattern_is_tiled(const texture_tile_pattern *p);
/* The path as given. */
const char *texture_tile_pattern_text(const texture_tile_pattern *p);

/* The path of `tile` (malloc'd; the caller frees it); a plain path is the
 * same for every tile. */
nbrdf_status texture_tile_pattern_path(const texture_tile_pattern *p, int tile, char **path,
                                       nbrdf_error *err);

/* The tiles present on disk for a tiled pattern: the regular files (or links
 * to them) of the pattern's folder whose names match it, ascending, in
 * tiles[0 .. *n). A name that matches but names no valid tile (tile 1200,
 * u10, a leading zero) is NBRDF_ERR_ARGUMENT naming the file, rather than
 * left out quietly; a folder that cannot be read is NBRDF_ERR_IO. No match
 * is *n = 0 and NBRDF_OK. */
nbrdf_status texture_tile_pattern_list(const texture_tile_pattern *p, int tiles[TEXTURE_TILE_COUNT],
                                       int *n, nbrdf_error *err);

#endif
