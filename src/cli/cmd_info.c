/* nbrdf info: what a user needs to know about a latent texture. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_tiles.h"
#include "cli/info_tiles.h"
#include "texture/latent_exr.h"

typedef struct info_args {
  const char *path;
  int header_only;
} info_args;

static void info_options(info_args *a, cli_opt_visit visit, void *user) {
  // clang-format off
  const cli_opt t[] = {
      {.type = CLI_OPT_FLAG, .name = "--header-only", .dest = &a->header_only, .value = 1,
       .help = "read the header only (instant; a truncated or damaged tile\n"
               "goes unnoticed)"},
      {0},
  };
  // clang-format on
  visit(user, NULL, t);
}

void cmd_info_options(cli_opt_visit visit, void *user) {
  info_args a = {NULL, 0};
  info_options(&a, visit, user);
}

void cmd_info_usage(FILE *out) {
  fprintf(out, "usage: nbrdf info [--header-only] TEXTURE.exr\n"
               "       nbrdf info [--header-only] 'TEXTURE.<UDIM>.exr'\n"
               "\n"
               "Prints a latent texture's size, mip levels, channels, colour mode, storage,\n"
               "compression, the model that baked it (name and checksum), its parameter\n"
               "sources and bake settings, and its decoder: 'own' when the texture carries\n"
               "one (format version 2, with its size and checksum), else 'bundle'\n"
               "(docs/LATENT-TEXTURE.md). Then checks the whole file: an own decoder must\n"
               "parse and fit the latents, and every tile of every level is read and\n"
               "decoded and every value must be finite\n"
               "(about 0.4 s of CPU for a 1024 x 1024 half texture; docs/LATENT-TEXTURE.md).\n"
               "A tile pattern (docs/FARM.md, \"Tile sets\") gives a line per tile, then what\n"
               "the tiles share (size, format, model, accuracy, decoder) or that they differ.\n"
               "\n");
  cmd_info_options(cli_options_help_visit, out);
  fprintf(out, "\n"
               "exit status: 0 success, 1 failure (unreadable, truncated, damaged or not a latent\n"
               "texture; the message names the file, and the level and tile of a damaged one),\n"
               "2 bad usage\n");
}

int cmd_info(int argc, char **argv) {
  info_args a = {NULL, 0};
  cli_positionals pos = {&a.path, 1, 0, "texture"};
  cli_parse_call call = {"info", NULL, argc, 1, argv, &pos, 0};
  info_options(&a, cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) {
    cmd_info_usage(stdout);
    return CLI_EXIT_OK;
  }
  if (call.rc != CLI_OPTIONS_OK) return call.rc;
  const char *path = a.path;
  int header_only = a.header_only;
  if (!path) return cli_usage_error("info", "needs a texture file");
  if (cli_tiles_is_pattern(path)) return info_tiles_run(path, header_only);
  nbrdf_error err = {0};
  texture_latent_reader *r = NULL;
  if (texture_latent_reader_open(&r, path, &err) != NBRDF_OK) return cli_fail_error("info", &err);
  const texture_latent_info *in = texture_latent_reader_info(r);
  printf("file:          %s (%lld bytes)\n", path, (long long)in->file_size);
  printf("size:          %d x %d\n", in->width, in->height);
  printf("levels:        %d:", in->levels);
  for (int l = 0; l < in->levels; l++) {
    int w = 0, h = 0;
    if (texture_latent_reader_level_size(r, l, &w, &h, &err) != NBRDF_OK) break;
    printf(" %dx%d", w, h);
  }
  printf("\n");
  printf("tiles:         %d x %d\n", in->tile_width, in->tile_height);
  printf("colour mode:   %s\n", texture_colour_mode_name(in->layout.colour));
  printf("channels:      %d (latent dim %d per colour channel%s)\n", in->channels,
         in->layout.latent_dim, in->layout.proxy ? ", plus proxy sigma and w" : "");
  printf("storage:       %s\n", texture_latent_storage_name(in->storage));
  printf("compression:   %s\n", texture_latent_compression_name(in->compression));
  printf("format:        version %d, mip filter %s\n", in->format_version, in->mip_filter);
  printf("model:         %s (checksum %s)\n", in->model_name, in->model_checksum);
  printf("sources:       %s\n", in->sources);
  printf("bake settings: %s\n", in->settings);
  if (in->accuracy[0]) printf("accuracy: %s\n", in->accuracy);
  if (in->inputs[0]) printf("inputs:        %s\n", in->inputs);
  printf("writer:        %s\n", in->writer);
  if (in->decoder_size)
    printf("decoder:       own (%zu bytes, checksum %s)\n", in->decoder_size, in->decoder_checksum);
  else
    printf("decoder:       bundle\n");
  if (isnan(in->max_albedo))
    printf("max albedo:    not recorded (baked without the energy audit)\n");
  else
    printf("max albedo:    %.4f (largest decoded directional albedo of the audited latents%s)\n",
           in->max_albedo, in->max_albedo > 1.01 ? ": above 1.01, the model creates energy" : "");
  int rc = CLI_EXIT_OK;
  char about[160];
  fflush(stdout); /* what the header says comes out before the check's verdict */
  if (header_only) {
    printf("check:         header only (--header-only)\n");
  } else if (texture_latent_reader_check_decoder(r, about, sizeof about, &err) != NBRDF_OK ||
             texture_latent_reader_check(r, &err) != NBRDF_OK) {
    printf("check:         FAILED\n");
    rc = cli_fail_error("info", &err);
  } else {
    printf("check:         every tile of %d level(s) read, all values finite%s%s\n", in->levels,
           about[0] ? "; own decoder: " : "", about);
  }
  texture_latent_reader_close(r);
  return rc;
}
