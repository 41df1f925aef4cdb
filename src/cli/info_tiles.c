#include "cli/info_tiles.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_tiles.h"
#include "texture/latent_exr.h"

/* What the set's summary compares across tiles (copies: each tile's reader is closed). */
typedef struct tile_summary {
  int width, height, levels, mono;
  texture_latent_storage storage;
  char model[160], decoder[32], accuracy[32];
} tile_summary;

static tile_summary summarise(const texture_latent_info *in) {
  tile_summary s = {in->width,   in->height, in->levels, in->layout.colour == NBRDF_COLOUR_MONO,
                    in->storage, "",         "",         ""};
  snprintf(s.model, sizeof s.model, "%s (checksum %s)", in->model_name, in->model_checksum);
  snprintf(s.decoder, sizeof s.decoder, "%s", in->decoder_size ? in->decoder_checksum : "");
  /* "level=fitted; budget=…": the level alone; a fast bake writes none */
  const char *level = in->accuracy;
  if (!strncmp(level, "level=", 6)) level += 6;
  size_t n = strcspn(level, ";");
  snprintf(s.accuracy, sizeof s.accuracy, "%.*s", n ? (int)n : 4, n ? level : "fast");
  return s;
}

/* One tile's line; 1 when it was read (and checked), else 0 after its FAILED line. */
static int info_tile(int tile, const char *path, int header_only, tile_summary *s,
                     long long *bytes) {
  nbrdf_error err = {0};
  texture_latent_reader *r = NULL;
  char about[160] = "";
  int ok = texture_latent_reader_open(&r, path, &err) == NBRDF_OK;
  if (ok) {
    const texture_latent_info *in = texture_latent_reader_info(r);
    *s = summarise(in);
    *bytes += in->file_size;
    printf("tile %d: %s, %d x %d %s, %d level(s), %s %s, %lld bytes, decoder %s%s", tile, path,
           in->width, in->height, texture_colour_mode_name(in->layout.colour), in->levels,
           texture_latent_storage_name(in->storage),
           texture_latent_compression_name(in->compression), (long long)in->file_size,
           in->decoder_size ? "own " : "bundle", in->decoder_size ? in->decoder_checksum : "");
    ok = header_only ||
         (texture_latent_reader_check_decoder(r, about, sizeof about, &err) == NBRDF_OK &&
          texture_latent_reader_check(r, &err) == NBRDF_OK);
    if (ok) printf(", %s\n", header_only ? "header only" : "check ok");
  } else {
    printf("tile %d: %s", tile, path);
  }
  if (!ok) printf(": FAILED: %s\n", err.message);
  texture_latent_reader_close(r);
  return ok;
}

int info_tiles_run(const char *pattern, int header_only) {
  texture_tile_set set;
  int rc = cli_tiles_list("info", pattern, &set);
  if (rc != CLI_EXIT_OK) return rc;
  tile_summary first = {0}, s;
  int read = 0, failed = 0, same_size = 1, same_format = 1, same_model = 1, same_decoder = 1,
      same_accuracy = 1;
  long long bytes = 0;
  for (int i = 0; i < set.count; i++) {
    char *path = cli_tiles_path("info", pattern, set.tiles[i]);
    if (!path) return CLI_EXIT_FAILURE;
    int ok = info_tile(set.tiles[i], path, header_only, &s, &bytes);
    free(path);
    fflush(stdout);
    if (!ok) {
      failed++;
      continue;
    }
    if (read++ == 0) {
      first = s;
      continue;
    }
    same_size &= s.width == first.width && s.height == first.height && s.levels == first.levels;
    same_format &= s.mono == first.mono && s.storage == first.storage;
    same_model &= !strcmp(s.model, first.model);
    same_decoder &= !strcmp(s.decoder, first.decoder);
    same_accuracy &= !strcmp(s.accuracy, first.accuracy);
  }
  printf("set:           %s, %d tile(s) %d..%d, %lld bytes\n", pattern, set.count, set.tiles[0],
         set.tiles[set.count - 1], bytes);
  if (read) {
    if (same_size)
      printf("size:          %d x %d, %d level(s), every tile\n", first.width, first.height,
             first.levels);
    else
      printf("size:          differs between tiles\n");
    if (same_format)
      printf("format:        %s, %s, every tile\n", first.mono ? "mono" : "rgb",
             texture_latent_storage_name(first.storage));
    else
      printf("format:        colour mode or storage differs between tiles\n");
    printf("model:         %s\n", same_model ? first.model : "differs between tiles");
    printf("accuracy:      %s\n", same_accuracy ? first.accuracy : "differs between tiles");
    if (same_decoder)
      printf("decoder:       %s%s, every tile\n", first.decoder[0] ? "own, checksum " : "bundle",
             first.decoder);
    else
      printf("decoder:       differs between tiles (each tile fitted on its own: seams may "
             "show)\n");
  }
  if (failed) {
    printf("check:         FAILED: %d of %d tile(s)\n", failed, set.count);
    return cli_fail("info", "%s: %d of %d tile(s) unreadable or damaged (listed above)", pattern,
                    failed, set.count);
  }
  printf("check:         %s\n", header_only ? "header only (--header-only)"
                                            : "every tile of every level read, all values finite");
  return CLI_EXIT_OK;
}
