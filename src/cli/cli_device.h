/* --device auto|cpu|gpu and $NBRDF_DEVICE: where a command's networks run (docs/GPU.md). */
#ifndef NBRDF_CLI_CLI_DEVICE_H
#define NBRDF_CLI_CLI_DEVICE_H

#include "nbrdf/model.h"

/* Usage lines of the option. */
#define CLI_DEVICE_USAGE                                                                           \
  "  --device auto|cpu|gpu the networks' device (default $NBRDF_DEVICE, else auto): auto\n"        \
  "                        a GPU where Vulkan has one (else the CPU, with a note), gpu a\n"        \
  "                        GPU or an error; NBRDF_VK_DEVICE=NAME picks one by name\n"

/* The default: $NBRDF_DEVICE when set, else AUTO. Returns -1 (after a usage message naming
 * `cmd`) when the variable holds something else. */
int cli_device_default(const char *cmd, nbrdf_device *device);
/* "--device V": 1 when argv[*i] is it (advancing *i; *device set), 0 when not, -1 on a bad
 * value (usage message printed). */
int cli_device_option(const char *cmd, int argc, char **argv, int *i, nbrdf_device *device);
/* Prints a library note: "nbrdf CMD: note: MESSAGE" on stderr. user: the command's name. */
void cli_device_note(void *cmd, const char *message);

#endif
