/* What a command reads, gathered in one place, and the check that none of its
 * outputs is one of those files (docs/RELIABILITY.md, "Outputs and signals").
 * Each writing command adds every input it has (maps, textures, the loaded
 * bundle's files, data sets, checkpoints, environment maps, OCIO configs) and
 * checks all its outputs before it writes anything; the writers check the
 * destination again when they create it (core/output_file.h). */
#ifndef NBRDF_CLI_OUTPUTS_H
#define NBRDF_CLI_OUTPUTS_H

#include "cli/cli_params.h"
#include "nbrdf/model.h"

#define CLI_INPUTS_MAX 128

typedef struct cli_inputs {
  const char *path[CLI_INPUTS_MAX]; /* borrowed: argv, or strings of a loaded model */
  int n;
  char *owned[CLI_INPUTS_MAX]; /* paths this list built (cli_inputs_add_bundle_dir) */
  int n_owned;
} cli_inputs;

void cli_inputs_init(cli_inputs *in);
void cli_inputs_free(cli_inputs *in);
/* NULL and "" are skipped; beyond CLI_INPUTS_MAX paths are dropped (never reached: 64 data
 * files at most plus a handful). */
void cli_inputs_add(cli_inputs *in, const char *path);
/* The six parameters' maps and the OCIO config. */
void cli_inputs_add_params(cli_inputs *in, const cli_params *p);
/* The files of a loaded model's bundle (nbrdf_model_files, the card included). */
void cli_inputs_add_model(cli_inputs *in, const nbrdf_model *model);
/* A bundle folder's files, before (or without) loading it. */
void cli_inputs_add_bundle_dir(cli_inputs *in, const char *dir);

/* CLI_EXIT_OK when every non-NULL output may be written: not an input, not a
 * directory, not a special file, not read-only, and no two outputs the same
 * file. Otherwise prints "nbrdf CMD: OUTPUT: ... the input 'INPUT' ..." and
 * returns CLI_EXIT_FAILURE. */
int cli_outputs_check(const char *cmd, const cli_inputs *in, const char *const *outputs,
                      int n_outputs);
/* One output. */
int cli_output_check(const char *cmd, const cli_inputs *in, const char *output);
/* The files `names` (NULL-terminated) in folder `dir` as outputs. */
int cli_outputs_check_in(const char *cmd, const cli_inputs *in, const char *dir,
                         const char *const *names);
/* The files a bundle save writes into `dir` (model.json, the four .safetensors,
 * MODEL_CARD.md): all checked before the first is replaced. */
int cli_outputs_check_bundle(const char *cmd, const cli_inputs *in, const char *dir);

#endif
