/* The accuracy levels' own error estimate without writing a texture: runs the
 * selection, ground truth and fit of a level (bake_accuracy_fit) on a
 * scene and prints the median held-out lobe error next to the fast level's
 * on the same tuples. Measures `specialised` before the texture format that
 * carries a decoder exists, and the fit choices of docs/BAKE.md.
 *
 *   bench_ladder_heldout LEVEL BUDGET SEED --alpha1 V --eta V --alpha2 V --r0 V
 *                        --albedo V --sigma-t V      (V: a constant or a map) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake/bake_accuracy.h"
#include "bake/bake_sources.h"

int main(int argc, char **argv) {
  if (argc < 4 + 12) {
    fprintf(stderr, "usage: bench_ladder_heldout LEVEL BUDGET SEED --alpha1 V ... --sigma-t V\n");
    return 2;
  }
  nbrdf_error err = {0};
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  static const char *const names[NBRDF_BAKE_PARAM_COUNT] = {"--alpha1", "--eta", "--alpha2",
                                                            "--r0", "--albedo", "--sigma-t"};
  for (int i = 4; i + 1 < argc; i += 2)
    for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
      if (!strcmp(argv[i], names[id]) &&
          nbrdf_bake_param_parse(names[id] + 2, argv[i + 1], &in.param[id], &err) != NBRDF_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
      }
  nbrdf_model *model = NULL;
  if (nbrdf_model_load_default(&model, NULL, 0, &err) != NBRDF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.accuracy = (nbrdf_bake_accuracy)nbrdf_bake_accuracy_parse(argv[1]);
  o.budget = atof(argv[2]);
  o.seed = strtoull(argv[3], NULL, 10);
  texture_param_source *src[NBRDF_BAKE_PARAM_COUNT] = {0};
  bake_fit_result r;
  nbrdf_status st = bake_open_sources(&in, src, &err);
  int W = 0, H = 0, rgb = 0;
  if (st == NBRDF_OK)
    st = texture_param_sources_common_size(src, NBRDF_BAKE_PARAM_COUNT, &W, &H, &err);
  for (int id = 0; st == NBRDF_OK && id < NBRDF_BAKE_PARAM_COUNT; id++)
    rgb |= texture_param_source_channels(src[id]) == 3;
  if (W == 0) W = H = 1;
  bake_scene scene = {src, W, H, rgb ? 3 : 1};
  clock_t c0 = clock();
  if (st == NBRDF_OK) st = bake_accuracy_fit(model, &scene, 1, &o, NULL, &r, &err);
  if (st != NBRDF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  printf("%s budget %g: held-out median lobe error %.2f %% (fast %.2f %%), %zu fitted, %zu held "
         "out, %.1f CPU-s\n",
         argv[1], r.budget, 100 * r.heldout_error, 100 * r.heldout_error_fast, r.fitted, r.heldout,
         (double)(clock() - c0) / CLOCKS_PER_SEC);
  bake_fit_result_free(&r);
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    texture_param_source_free(src[id]);
  nbrdf_model_destroy(model);
  return 0;
}
