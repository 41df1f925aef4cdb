#include "cli/cli_device.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

int cli_device_default(const char *cmd, nbrdf_device *device) {
  const char *env = getenv("NBRDF_DEVICE");
  *device = NBRDF_DEVICE_AUTO;
  if (!env || !*env) return 0;
  int d = nbrdf_device_parse(env);
  if (d < 0) {
    cli_usage_error(cmd, "NBRDF_DEVICE is auto, cpu or gpu, not '%s'", env);
    return -1;
  }
  *device = (nbrdf_device)d;
  return 0;
}

int cli_device_option(const char *cmd, int argc, char **argv, int *i, nbrdf_device *device) {
  const char *a = argv[*i];
  const char *v = NULL;
  if (!strncmp(a, "--device=", 9))
    v = a + 9;
  else if (!strcmp(a, "--device") && *i + 1 < argc)
    v = argv[++*i];
  else
    return 0;
  int d = nbrdf_device_parse(v);
  if (d < 0) {
    cli_usage_error(cmd, "--device is auto, cpu or gpu, not '%s'", v);
    return -1;
  }
  *device = (nbrdf_device)d;
  return 1;
}

void cli_device_note(void *cmd, const char *message) {
  fprintf(stderr, "nbrdf %s: note: %s\n", (const char *)cmd, message);
}
