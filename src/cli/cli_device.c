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

const int cli_device_values[3] = {NBRDF_DEVICE_AUTO, NBRDF_DEVICE_CPU, NBRDF_DEVICE_GPU};

void cli_device_note(void *cmd, const char *message) {
  fprintf(stderr, "nbrdf %s: note: %s\n", (const char *)cmd, message);
}
