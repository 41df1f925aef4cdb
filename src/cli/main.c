#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_blas.h"
#include "cli/cli_cancel.h"
#include "nbrdf/nbrdf.h"
#include "texture/oiio_shim.h"

int main(int argc, char **argv) {
  cli_blas_prefer_wide(argv);
  cli_signals_setup();
  /* One message per failure, nbrdf's: libpng's own stderr line is folded into it. */
  texture_image_capture_stderr(1);
  if (argc < 2) {
    cli_commands[0].run(1, argv); /* the overview of 'help' */
    return CLI_EXIT_USAGE;
  }
  const char *name = argv[1];
  if (!strcmp(name, "--version") || !strcmp(name, "version")) {
    printf("nbrdf %s\n", nbrdf_version());
    cli_blas_describe(stdout);
    cli_bundle_describe(stdout);
    return CLI_EXIT_OK;
  }
  if (cli_is_help(name)) name = "help";
  for (int i = 0; i < cli_command_count; i++) {
    if (!strcmp(cli_commands[i].name, name)) {
      if (argc > 2 && cli_is_help(argv[2])) {
        cli_commands[i].usage(stdout);
        return CLI_EXIT_OK;
      }
      return cli_commands[i].run(argc - 1, argv + 1);
    }
  }
  fprintf(stderr, "nbrdf: unknown command '%s' (see 'nbrdf help')\n", name);
  return CLI_EXIT_USAGE;
}
