/* The six layered-BRDF parameter inputs on the command line, shared by the
 * commands that take them (`nbrdf bake`, `nbrdf verify`), so that a texture
 * is verified with exactly the options it was baked with. */
#ifndef NBRDF_CLI_PARAMS_H
#define NBRDF_CLI_PARAMS_H

#include <stdio.h>

#include "nbrdf/bake.h"

typedef struct cli_params {
  nbrdf_bake_inputs in;
  int given[NBRDF_BAKE_PARAM_COUNT];
  nbrdf_roughness roughness;
  int roughness_given;
} cli_params;

/* The bake's defaults: 8/16-bit eta maps span [1, 2], sigma_t maps [0, 5]. */
void cli_params_init(cli_params *p);
/* If argv[*i] is a parameter option (--alpha1 V ... --sigma-t V, --roughness,
 * --r0-colourspace, --albedo-colourspace, --ocio, --eta-range,
 * --sigma-t-range, --resample) with its value, consumes it (advancing *i) and returns 1;
 * returns 0 for any other argument, and -1 after printing a usage error. */
int cli_params_option(const char *cmd, int argc, char **argv, int *i, cli_params *p);
/* CLI_EXIT_OK when all six parameters were given, else a usage error naming one. */
int cli_params_require(const char *cmd, const cli_params *p);
/* Says a failure of the maps in the options' words: a size mismatch's neutral
 * advice (TEXTURE_RESAMPLE_ADVICE) becomes "pass --resample bilinear". In place,
 * so that the JSON error event says the same. */
void cli_params_explain(nbrdf_error *err);
/* The help lines of the options above. */
void cli_params_usage(FILE *out);

#endif
