/* A program linking the installed libnbrdf: bakes two constant-parameter latent textures
 * (a grey lacquered metal and a red-tinted one) with the default model bundle, found without
 * a path (nbrdf_model_load_default: $NBRDF_BUNDLE, else the installed one).
 *
 *   usage: nbrdf_consumer OUT_DIR        writes OUT_DIR/grey.exr and OUT_DIR/red.exr
 *
 * Build it against an installed nbrdf with CMake (CMakeLists.txt here) or pkg-config:
 *   cc -std=c11 main.c $(pkg-config --cflags --libs nbrdf) -o nbrdf_consumer */
#include <limits.h>
#include <stdio.h>

#include "nbrdf/bake.h"
#include "nbrdf/model.h"
#include "nbrdf/nbrdf.h"

static int bake(const nbrdf_model *model, const char *dir, const char *name, float r0_red) {
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA1], 0.1f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ETA], 1.5f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA2], 0.3f);
  nbrdf_bake_param *r0 = &in.param[NBRDF_BAKE_R0];
  r0->channels = 3;
  r0->value[0] = r0_red, r0->value[1] = 0.6f, r0->value[2] = 0.5f;
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALBEDO], 0.7f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_SIGMA_T], 1.0f);

  char path[PATH_MAX];
  snprintf(path, sizeof path, "%s/%s.exr", dir, name);
  nbrdf_bake_options opts = NBRDF_BAKE_OPTIONS_DEFAULT;
  nbrdf_error err = {0};
  if (nbrdf_bake(model, &in, &opts, path, NULL, &err) != NBRDF_OK) {
    fprintf(stderr, "nbrdf_consumer: %s: %s\n", path, err.message);
    return 1;
  }
  printf("baked %s\n", path);
  return 0;
}

int main(int argc, char **argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: nbrdf_consumer OUT_DIR\n");
    return 2;
  }
  char bundle[PATH_MAX];
  nbrdf_model *model = NULL;
  nbrdf_error err = {0};
  if (nbrdf_model_load_default(&model, bundle, sizeof bundle, &err) != NBRDF_OK) {
    fprintf(stderr, "nbrdf_consumer: %s\n", err.message);
    return 1;
  }
  printf("nbrdf %s, bundle %s (checksum %s)\n", nbrdf_version(), bundle,
         nbrdf_model_checksum(model));
  int rc = bake(model, argv[1], "grey", 0.6f) || bake(model, argv[1], "red", 0.9f);
  nbrdf_model_destroy(model);
  return rc;
}
