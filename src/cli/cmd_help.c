#include <string.h>

#include "cli/cli.h"
#include "nbrdf/nbrdf.h"

void cmd_help_usage(FILE *out) {
  fprintf(out,
          "usage: nbrdf help [COMMAND]\n"
          "Shows the list of commands, or the help of one command.\n");
}

static void overview(FILE *out) {
  fprintf(out,
          "nbrdf %s: neural layered BRDFs (Fan et al. 2022)\n\n"
          "usage: nbrdf [--version] <command> [options]\n\ncommands:\n",
          nbrdf_version());
  for (int i = 0; i < cli_command_count; i++)
    fprintf(out, "  %-10s %s\n", cli_commands[i].name, cli_commands[i].summary);
  fprintf(out, "\n'nbrdf <command> --help' shows a command's options.\n");
}

int cmd_help(int argc, char **argv) {
  if (argc <= 1) {
    overview(stdout);
    return CLI_EXIT_OK;
  }
  if (cli_is_help(argv[1])) {
    cmd_help_usage(stdout);
    return CLI_EXIT_OK;
  }
  for (int i = 0; i < cli_command_count; i++) {
    if (!strcmp(cli_commands[i].name, argv[1])) {
      cli_commands[i].usage(stdout);
      return CLI_EXIT_OK;
    }
  }
  return cli_usage_error("help", "unknown command '%s'", argv[1]);
}
