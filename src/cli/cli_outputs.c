#include "cli/cli_outputs.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/cli.h"
#include "core/output_file.h"

void cli_inputs_init(cli_inputs *in) { memset(in, 0, sizeof *in); }

void cli_inputs_free(cli_inputs *in) {
  for (int i = 0; i < in->n_owned; i++)
    free(in->owned[i]);
  cli_inputs_init(in);
}

void cli_inputs_add(cli_inputs *in, const char *path) {
  if (path && path[0] && in->n < CLI_INPUTS_MAX) in->path[in->n++] = path;
}

void cli_inputs_add_params(cli_inputs *in, const cli_params *p) {
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    cli_inputs_add(in, p->in.param[id].path);
  cli_inputs_add(in, p->in.ocio_config);
}

void cli_inputs_add_model(cli_inputs *in, const nbrdf_model *model) {
  if (!model) return;
  const char *const *files;
  int n = nbrdf_model_files(model, &files);
  for (int i = 0; i < n; i++)
    cli_inputs_add(in, files[i]);
}

static const char *const bundle_files[] = {"model.json",
                                           "decoder.safetensors",
                                           "layering.safetensors",
                                           "sampler.safetensors",
                                           "base_tables.safetensors",
                                           "MODEL_CARD.md",
                                           NULL};

void cli_inputs_add_bundle_dir(cli_inputs *in, const char *dir) {
  const char *const *names = bundle_files;
  if (!dir || !dir[0]) return;
  for (size_t i = 0; i < 5; i++) { /* the card is not read */
    if (in->n_owned == CLI_INPUTS_MAX) return;
    size_t len = strlen(dir) + strlen(names[i]) + 2;
    char *path = malloc(len);
    if (!path) return;
    snprintf(path, len, "%s/%s", dir, names[i]);
    in->owned[in->n_owned++] = path;
    cli_inputs_add(in, path);
  }
}

static int same_file(const char *a, const char *b) {
  if (!strcmp(a, b)) return 1;
  struct stat sa, sb;
  return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

int cli_outputs_check(const char *cmd, const cli_inputs *in, const char *const *outputs,
                      int n_outputs) {
  for (int i = 0; i < n_outputs; i++) {
    if (!outputs[i]) continue;
    nbrdf_error err = {0};
    if (core_output_check(outputs[i], in->path, in->n, &err) != NBRDF_OK)
      return cli_fail_error(cmd, &err);
    for (int j = 0; j < i; j++)
      if (outputs[j] && same_file(outputs[i], outputs[j]))
        return cli_fail(cmd, "%s: named for two outputs ('%s' too); refusing", outputs[i],
                        outputs[j]);
  }
  return CLI_EXIT_OK;
}

int cli_output_check(const char *cmd, const cli_inputs *in, const char *output) {
  return cli_outputs_check(cmd, in, &output, 1);
}

/* A folder the command will create (mkdir -p) holds no input and no file to replace: its
 * first missing component must be creatable where it goes. Sets *missing. */
static int check_new_folder(const char *cmd, const char *dir, int *missing) {
  char path[4096], first[4096];
  int n = snprintf(path, sizeof path, "%s", dir);
  if (n < 0 || n >= (int)sizeof path) return cli_fail(cmd, "%s: path too long", dir);
  *missing = 0;
  struct stat sb;
  while (path[0] && stat(path, &sb) != 0 && errno == ENOENT) {
    *missing = 1;
    memcpy(first, path, (size_t)n + 1);
    char *slash = strrchr(path, '/');
    while (slash && slash > path && slash[1] == '\0') { /* "a/b/" */
      *slash = '\0';
      slash = strrchr(path, '/');
    }
    if (!slash) break;
    *slash = '\0';
    n = (int)(slash - path);
  }
  if (!*missing) return CLI_EXIT_OK;
  nbrdf_error err = {0};
  if (core_output_check(first, NULL, 0, &err) != NBRDF_OK) return cli_fail_error(cmd, &err);
  return CLI_EXIT_OK;
}

int cli_outputs_check_in(const char *cmd, const cli_inputs *in, const char *dir,
                         const char *const *names) {
  int missing = 0;
  if (check_new_folder(cmd, dir, &missing) != CLI_EXIT_OK) return CLI_EXIT_FAILURE;
  if (missing) return CLI_EXIT_OK;
  for (int i = 0; names[i]; i++) {
    char path[4096];
    int n = snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    if (n < 0 || n >= (int)sizeof path) return cli_fail(cmd, "%s: path too long", dir);
    if (cli_output_check(cmd, in, path) != CLI_EXIT_OK) return CLI_EXIT_FAILURE;
  }
  return CLI_EXIT_OK;
}

int cli_outputs_check_bundle(const char *cmd, const cli_inputs *in, const char *dir) {
  return cli_outputs_check_in(cmd, in, dir, bundle_files);
}
