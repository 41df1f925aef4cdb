#include <string.h>

#include "cli/cli.h"
#include "nbrdf/nbrdf.h"

void cmd_help_usage(FILE *out) {
  fprintf(out, "usage: nbrdf help [COMMAND]\n"
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

void cmd_help_options(cli_opt_visit visit, void *user) {
  const cli_opt none[] = {{0}};
  visit(user, NULL, none);
}

int cmd_help(int argc, char **argv) {
  const char *name = NULL;
  cli_positionals pos = {&name, 1, 0, "command"};
  cli_parse_call call = {"help", NULL, argc, 1, argv, &pos, 0};
  cmd_help_options(cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) {
    cmd_help_usage(stdout);
    return CLI_EXIT_OK;
  }
  if (call.rc != CLI_OPTIONS_OK) return call.rc;
  if (!name) {
    overview(stdout);
    return CLI_EXIT_OK;
  }
  for (int i = 0; i < cli_command_count; i++) {
    if (!strcmp(cli_commands[i].name, name)) {
      cli_commands[i].usage(stdout);
      return CLI_EXIT_OK;
    }
  }
  return cli_usage_error("help", "unknown command '%s'", name);
}
