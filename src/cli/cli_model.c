/* The model a command runs on: --bundle DIR, or the library's default-bundle lookup. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>

#include "cli/cli_common.h"
#include "nbrdf/model.h"

int cli_model_load(const char *cmd, const char *bundle, nbrdf_model **out, char *used,
                   size_t size) {
  nbrdf_error err = {0};
  char dir[PATH_MAX];
  if (bundle) {
    snprintf(dir, sizeof dir, "%s", bundle);
  } else if (nbrdf_default_bundle_path(dir, sizeof dir, &err) != NBRDF_OK) {
    return cli_fail(cmd, "%s; pass --bundle DIR", err.message);
  }
  if (used && size > 0) snprintf(used, size, "%s", dir);
  if (nbrdf_model_load(dir, out, &err) != NBRDF_OK) {
    const char *env = getenv("NBRDF_BUNDLE");
    if (!bundle && env && env[0]) return cli_fail(cmd, "$NBRDF_BUNDLE=%s: %s", env, err.message);
    return cli_fail_error(cmd, &err);
  }
  return CLI_EXIT_OK;
}

void cli_bundle_describe(FILE *out) {
  nbrdf_error err = {0};
  char dir[PATH_MAX];
  if (nbrdf_default_bundle_path(dir, sizeof dir, &err) == NBRDF_OK) {
    const char *env = getenv("NBRDF_BUNDLE");
    fprintf(out, "bundle: %s%s\n", dir, env && env[0] ? " (from $NBRDF_BUNDLE)" : "");
  } else {
    fprintf(out, "bundle: none: %s\n", err.message);
  }
}
