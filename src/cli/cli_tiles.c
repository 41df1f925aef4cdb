#include "cli/cli_tiles.h"

#include <string.h>
#include <sys/stat.h>

#include "cli/cli.h"

int cli_tiles_is_pattern(const char *arg) {
  struct stat sb;
  if (!arg || stat(arg, &sb) == 0) return 0;
  texture_tile_pattern *p = NULL;
  nbrdf_error err = {0};
  if (texture_tile_pattern_parse(arg, &p, &err) != NBRDF_OK) return 0;
  int tiled = texture_tile_pattern_is_tiled(p);
  texture_tile_pattern_free(p);
  return tiled;
}

int cli_tiles_list(const char *cmd, const char *pattern, texture_tile_set *set) {
  /* One map's tiles are what texture_tile_set_resolve finds, messages included. */
  texture_tile_map map = {"texture", pattern};
  nbrdf_error err = {0};
  nbrdf_status st = texture_tile_set_resolve(&map, 1, set, &err);
  if (st == NBRDF_ERR_ARGUMENT) return cli_usage_error(cmd, "%s", err.message);
  if (st != NBRDF_OK) return cli_fail_error(cmd, &err);
  return CLI_EXIT_OK;
}

char *cli_tiles_path(const char *cmd, const char *pattern, int tile) {
  texture_tile_pattern *p = NULL;
  nbrdf_error err = {0};
  char *path = NULL;
  if (texture_tile_pattern_parse(pattern, &p, &err) != NBRDF_OK ||
      texture_tile_pattern_path(p, tile, &path, &err) != NBRDF_OK)
    cli_fail_error(cmd, &err);
  texture_tile_pattern_free(p);
  return path;
}
