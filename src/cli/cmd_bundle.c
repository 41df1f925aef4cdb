/* nbrdf bundle: create an untrained model bundle, or describe one. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "cli/cli_outputs.h"
#include "model/bundle.h"

void cmd_bundle_usage(FILE *out) {
  fprintf(out,
          "usage: nbrdf bundle init DIR [--name NAME] [--seed S] [--decoder PRESET] [--force]\n"
          "       nbrdf bundle info DIR\n"
          "\n"
          "A model bundle is a folder with decoder.safetensors, layering.safetensors,\n"
          "sampler.safetensors, base_tables.safetensors, model.json and MODEL_CARD.md.\n"
          "\n"
          "init  writes a complete bundle of RANDOMLY INITIALISED networks and base tables of\n"
          "      smooth random latents, marked untrained in model.json and the card: its BRDF\n"
          "      values mean nothing, but the bake, the evaluator, the Blender add-on and the\n"
          "      shaders can be built and tested with it before training finishes.\n"
          "      --name NAME       model name (default: the folder's last component)\n"
          "      --seed S          unsigned 64-bit seed (default 1); same seed, same bytes\n"
          "      --decoder PRESET  paper (1.06 M MACs/query), large (103 k), medium (27 k),\n"
          "                        small (5.3 k; default)\n"
          "      --force           replace a bundle already in DIR (refused otherwise)\n"
          "info  loads and validates a bundle and prints its name, checksum, architecture,\n"
          "      multiply-adds per query and base-table grids.\n"
          "\n"
          "exit status: 0 success, 1 failure (the message names the file), 2 bad usage\n");
}

static int bundle_init(int argc, char **argv) {
  const char *dir = NULL, *name = NULL, *preset = "small";
  uint64_t seed = 1;
  int force = 0;
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    if (!strcmp(a, "--name") && i + 1 < argc) {
      name = argv[++i];
    } else if (!strcmp(a, "--seed") && i + 1 < argc) {
      if (!cli_parse_u64(argv[++i], &seed))
        return cli_usage_error("bundle", "--seed needs an unsigned 64-bit integer, not '%s'",
                               argv[i]);
    } else if (!strcmp(a, "--decoder") && i + 1 < argc) {
      preset = argv[++i];
    } else if (!strcmp(a, "--force")) {
      force = 1;
    } else if (a[0] == '-') {
      return cli_usage_error("bundle", "unknown option or missing value: '%s'", a);
    } else if (!dir) {
      dir = a;
    } else {
      return cli_usage_error("bundle", "init takes one folder, got '%s' and '%s'", dir, a);
    }
  }
  if (!dir) return cli_usage_error("bundle", "init needs a folder");
  int known = 0;
  for (int p = 0; model_decoder_presets[p]; p++)
    known |= !strcmp(preset, model_decoder_presets[p]);
  if (!known)
    return cli_usage_error("bundle", "unknown decoder preset '%s' (paper, large, medium, small)",
                           preset);
  char json[4096];
  snprintf(json, sizeof json, "%s/model.json", dir);
  if (!force && access(json, F_OK) == 0)
    return cli_fail("bundle", "%s already holds a bundle; use --force to replace it", dir);
  if (!name) {
    size_t len = strlen(dir);
    while (len > 1 && dir[len - 1] == '/')
      len--;
    size_t start = len;
    while (start > 0 && dir[start - 1] != '/')
      start--;
    static char base[64];
    size_t n = len - start < sizeof base - 1 ? len - start : sizeof base - 1;
    memcpy(base, dir + start, n);
    base[n] = '\0';
    name = n > 0 && strcmp(base, ".") && strcmp(base, "..") ? base : "untrained";
  }
  cli_inputs none; /* nothing read; the files replaced are still checked */
  cli_inputs_init(&none);
  if (cli_outputs_check_bundle("bundle", &none, dir) != CLI_EXIT_OK) return CLI_EXIT_FAILURE;
  nbrdf_error err = {0};
  if (model_bundle_init_random(dir, name, seed, preset, &err) != NBRDF_OK)
    return cli_fail_error("bundle", &err);
  nbrdf_model *m = NULL;
  if (nbrdf_model_load(dir, &m, &err) != NBRDF_OK) return cli_fail_error("bundle", &err);
  printf("wrote untrained bundle '%s' to %s (checksum %s, decoder %s)\n", nbrdf_model_name(m), dir,
         nbrdf_model_checksum(m), preset);
  nbrdf_model_destroy(m);
  return CLI_EXIT_OK;
}

static int bundle_info(int argc, char **argv) {
  if (argc != 3 || argv[2][0] == '-')
    return cli_usage_error("bundle", "info takes exactly one folder");
  nbrdf_error err = {0};
  nbrdf_model *m = NULL;
  if (nbrdf_model_load(argv[2], &m, &err) != NBRDF_OK) return cli_fail_error("bundle", &err);
  printf("bundle:    %s\n", argv[2]);
  model_bundle_describe(m, stdout);
  nbrdf_model_destroy(m);
  return CLI_EXIT_OK;
}

int cmd_bundle(int argc, char **argv) {
  if (argc < 2) return cli_usage_error("bundle", "missing action: init or info");
  if (!strcmp(argv[1], "init")) return bundle_init(argc, argv);
  if (!strcmp(argv[1], "info")) return bundle_info(argc, argv);
  return cli_usage_error("bundle", "unknown action '%s' (init or info)", argv[1]);
}
