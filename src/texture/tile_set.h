/* A tile set: the tiles that several maps' patterns (tile_pattern.h) agree
 * on. A bake of a set bakes one texture per tile, each from the maps' files
 * for that tile; a constant or a plain path applies to every tile. */
#ifndef NBRDF_TEXTURE_TILE_SET_H
#define NBRDF_TEXTURE_TILE_SET_H

#include "nbrdf/status.h"
#include "texture/tile_pattern.h"

/* One input of a set. */
typedef struct texture_tile_map {
  const char *name; /* how messages name it ("--alpha1", "alpha1") */
  const char *arg;  /* a constant ("0.3"), a plain path or a tile pattern */
} texture_tile_map;

typedef struct texture_tile_set {
  int count;                     /* 0: no map is tiled (not a set) */
  int tiles[TEXTURE_TILE_COUNT]; /* ascending */
} texture_tile_set;

/* The tiles of `n` maps: those present on disk for every tiled map. Each
 * tiled map must match at least one file (NBRDF_ERR_IO otherwise, naming the
 * map and the folder), and all tiled maps the same tiles: a disagreement is
 * NBRDF_ERR_MISMATCH naming the map lacking tiles, those tiles and the map
 * that has them ("--alpha2 'rough.<UDIM>.exr' has no tile 1003 (found in
 * --alpha1)"). A bad pattern is NBRDF_ERR_ARGUMENT prefixed with the map's
 * name. No tiled map: set->count = 0 and NBRDF_OK. */
nbrdf_status texture_tile_set_resolve(const texture_tile_map *maps, int n, texture_tile_set *set,
                                      nbrdf_error *err);

/* An output for `set`: a tile pattern when the set has tiles (one file per
 * tile), a plain path when it has none; NBRDF_ERR_ARGUMENT naming `name`
 * otherwise. */
nbrdf_status texture_tile_set_check_output(const texture_tile_set *set, const char *name,
                                           const char *arg, nbrdf_error *err);

/* Keeps in `set` the tiles that `list` names: tile numbers and ranges, comma-separated
 * ("1001,1003-1005"). A single tile the set lacks is NBRDF_ERR_ARGUMENT naming it and the
 * set's tiles; a range keeps the set's tiles within it and must hold one. A malformed list
 * is NBRDF_ERR_ARGUMENT quoting it. */
nbrdf_status texture_tile_set_select(texture_tile_set *set, const char *list, nbrdf_error *err);

/* 1 when `tile` is in the set. */
int texture_tile_set_has(const texture_tile_set *set, int tile);

#endif
