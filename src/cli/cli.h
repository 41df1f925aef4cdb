/* The nbrdf command-line tool: each subcommand lives in its own cmd_<name>.c
 * and is listed in commands.c. Subcommands parse, call the library, print. */
#ifndef NBRDF_CLI_H
#define NBRDF_CLI_H

#include <stdio.h>

#include "cli/cli_common.h"
#include "cli/cli_options.h"

typedef struct cli_command {
  const char *name;
  const char *summary;
  int (*run)(int argc, char **argv); /* argv[0] is the subcommand's name */
  void (*usage)(FILE *out);
  /* Shows the command's option tables (cli_options.h); NULL: it takes none. */
  void (*options)(cli_opt_visit visit, void *user);
} cli_command;

extern const cli_command cli_commands[];
extern const int cli_command_count;

#endif
