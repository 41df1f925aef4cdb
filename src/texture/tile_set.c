#include "texture/tile_set.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

/* At most this many tile numbers in a message, then "and N more". */
#define LISTED_TILES 8

int texture_tile_set_has(const texture_tile_set *set, int tile) {
  for (int i = 0; i < set->count; i++)
    if (set->tiles[i] == tile) return 1;
  return 0;
}

/* "tile 1003" or "tiles 1003, 1004 and 3 more": the tiles of `a` not in `b`;
 * 0 when there are none. */
static int missing_tiles(const texture_tile_set *a, const texture_tile_set *b, char *buf,
                         size_t size) {
  int missing[TEXTURE_TILE_COUNT], n = 0;
  for (int i = 0; i < a->count; i++)
    if (!texture_tile_set_has(b, a->tiles[i])) missing[n++] = a->tiles[i];
  if (n == 0) return 0;
  size_t at = (size_t)snprintf(buf, size, "tile%s ", n > 1 ? "s" : "");
  for (int i = 0; i < n && i < LISTED_TILES && at < size; i++)
    at += (size_t)snprintf(buf + at, size - at, "%s%d", i ? ", " : "", missing[i]);
  if (n > LISTED_TILES && at < size)
    snprintf(buf + at, size - at, " and %d more", n - LISTED_TILES);
  return n;
}

nbrdf_status texture_tile_set_resolve(const texture_tile_map *maps, int n, texture_tile_set *set,
                                      nbrdf_error *err) {
  set->count = 0;
  int first = -1; /* the first tiled map: the others are compared with it */
  for (int m = 0; m < n; m++) {
    texture_tile_pattern *p = NULL;
    nbrdf_status st = texture_tile_pattern_parse(maps[m].arg, &p, err);
    if (st != NBRDF_OK) {
      core_error_prefix(err, "%s: ", maps[m].name);
      return st;
    }
    if (!texture_tile_pattern_is_tiled(p)) {
      texture_tile_pattern_free(p);
      continue;
    }
    texture_tile_set here = {0};
    st = texture_tile_pattern_list(p, here.tiles, &here.count, err);
    texture_tile_pattern_free(p);
    if (st != NBRDF_OK) {
      core_error_prefix(err, "%s: ", maps[m].name);
      return st;
    }
    if (here.count == 0) {
      const char *slash = strrchr(maps[m].arg, '/');
      int dir_len = slash ? (slash == maps[m].arg ? 1 : (int)(slash - maps[m].arg)) : 1;
      return core_fail(err, NBRDF_ERR_IO, "%s '%s' matches no file in the folder %.*s",
                       maps[m].name, maps[m].arg, dir_len, slash ? maps[m].arg : ".");
    }
    if (first < 0) {
      first = m;
      *set = here;
      continue;
    }
    char list[160];
    if (missing_tiles(set, &here, list, sizeof list))
      return core_fail(err, NBRDF_ERR_MISMATCH, "%s '%s' has no %s (found in %s)", maps[m].name,
                       maps[m].arg, list, maps[first].name);
    if (missing_tiles(&here, set, list, sizeof list))
      return core_fail(err, NBRDF_ERR_MISMATCH, "%s '%s' has no %s (found in %s)", maps[first].name,
                       maps[first].arg, list, maps[m].name);
  }
  return NBRDF_OK;
}

nbrdf_status texture_tile_set_check_output(const texture_tile_set *set, const char *name,
                                           const char *arg, nbrdf_error *err) {
  texture_tile_pattern *p = NULL;
  nbrdf_status st = texture_tile_pattern_parse(arg, &p, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "%s: ", name);
    return st;
  }
  int tiled = texture_tile_pattern_is_tiled(p);
  texture_tile_pattern_free(p);
  if (set->count > 0 && !tiled)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s '%s' names one file, but the inputs are a set of %d tiles (%d..%d): "
                     "put a tile token such as <UDIM> in its name",
                     name, arg, set->count, set->tiles[0], set->tiles[set->count - 1]);
  if (set->count == 0 && tiled)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s '%s' is a tile pattern, but no input is a tile set: give the maps "
                     "with a tile token too, or name one output file",
                     name, arg);
  return NBRDF_OK;
}

/* One item of a --tiles list, `len` bytes at `text`: "1003" or "1003-1005". */
static nbrdf_status select_item(const texture_tile_set *set, const char *list, const char *text,
                                size_t len, texture_tile_set *kept, nbrdf_error *err) {
  char item[32], *dash;
  if (len == 0 || len >= sizeof item)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "tile list '%s': expected tile numbers and ranges, comma-separated "
                     "(1001,1003-1005)",
                     list);
  memcpy(item, text, len);
  item[len] = '\0';
  int lo, hi;
  dash = strchr(item, '-');
  if (dash) *dash = '\0';
  nbrdf_status st = texture_tile_parse(item, &lo, err);
  if (st == NBRDF_OK) st = dash ? texture_tile_parse(dash + 1, &hi, err) : NBRDF_OK;
  if (st != NBRDF_OK) {
    core_error_prefix(err, "tile list '%s': ", list);
    return st;
  }
  if (!dash) hi = lo;
  if (hi < lo)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "tile list '%s': range %d-%d runs backwards", list,
                     lo, hi);
  int found = 0;
  for (int i = 0; i < set->count; i++) {
    int t = set->tiles[i];
    if (t < lo || t > hi) continue;
    found = 1;
    if (!texture_tile_set_has(kept, t)) kept->tiles[kept->count++] = t;
  }
  if (!found)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "tile list '%s': the set has no tile%s %.*s (its %d tiles are %d..%d)", list,
                     dash ? "s in" : "", (int)len, text, set->count, set->count ? set->tiles[0] : 0,
                     set->count ? set->tiles[set->count - 1] : 0);
  return NBRDF_OK;
}

static int ascending(const void *a, const void *b) { return *(const int *)a - *(const int *)b; }

nbrdf_status texture_tile_set_select(texture_tile_set *set, const char *list, nbrdf_error *err) {
  texture_tile_set kept = {0};
  for (const char *c = list;;) {
    size_t len = strcspn(c, ",");
    nbrdf_status st = select_item(set, list, c, len, &kept, err);
    if (st != NBRDF_OK) return st;
    if (!c[len]) break;
    c += len + 1;
  }
  qsort(kept.tiles, (size_t)kept.count, sizeof kept.tiles[0], ascending);
  *set = kept;
  return NBRDF_OK;
}
