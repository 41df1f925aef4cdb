/* --device auto|cpu|gpu and $NBRDF_DEVICE: where a command's networks run (docs/GPU.md). */
#ifndef NBRDF_CLI_CLI_DEVICE_H
#define NBRDF_CLI_CLI_DEVICE_H

#include "cli/cli_options.h"
#include "nbrdf/model.h"

/* The option's table entry (cli_options.h); `device` an nbrdf_device *. */
extern const int cli_device_values[3];
// clang-format off
#define CLI_DEVICE_OPTION(device)                                                                  \
  {.type = CLI_OPT_ENUM, .name = "--device", .dest = (device), .choices = "auto|cpu|gpu",          \
   .values = cli_device_values,                                                                    \
   .help = "the networks' device (default $NBRDF_DEVICE, else auto): auto\n"                       \
           "a GPU where Vulkan has one (else the CPU, with a note), gpu a\n"                       \
           "GPU or an error; NBRDF_VK_DEVICE=NAME picks one by name"}
// clang-format on

/* The default: $NBRDF_DEVICE when set, else AUTO. Returns -1 (after a usage message naming
 * `cmd`) when the variable holds something else. */
int cli_device_default(const char *cmd, nbrdf_device *device);
/* Prints a library note: "nbrdf CMD: note: MESSAGE" on stderr. user: the command's name. */
void cli_device_note(void *cmd, const char *message);

#endif
