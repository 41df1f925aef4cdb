#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "core/number.h"

int cli_usage_error(const char *cmd, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fprintf(stderr, "nbrdf %s: ", cmd);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fprintf(stderr, "\n(see 'nbrdf %s --help')\n", cmd);
  return CLI_EXIT_USAGE;
}

int cli_fail(const char *cmd, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fprintf(stderr, "nbrdf %s: ", cmd);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fputc('\n', stderr);
  return CLI_EXIT_FAILURE;
}

int cli_fail_error(const char *cmd, const nbrdf_error *err) {
  return cli_fail(cmd, "%s", err->message[0] ? err->message : nbrdf_status_name(err->status));
}

int cli_parse_double(const char *text, double *out) {
  return text && nbrdf_parse_number(text, strlen(text), out) == NBRDF_NUMBER_OK;
}

int cli_parse_int(const char *text, long lo, long hi, long *out) {
  /* Decimal digits only (strtol would take "0x10" with base 0, and "12abc"
   * up to the letters), white space around them allowed as for numbers. */
  double v;
  if (!cli_parse_double(text, &v) || v != floor(v) || strpbrk(text, ".eE")) return 0;
  if (v < (double)lo || v > (double)hi) return 0;
  *out = (long)v;
  return 1;
}

int cli_is_help(const char *arg) { return !strcmp(arg, "-h") || !strcmp(arg, "--help"); }

const char *cli_option_value(int argc, char **argv, int *i, const char *name) {
  size_t n = strlen(name);
  if (strncmp(argv[*i], name, n)) return NULL;
  if (argv[*i][n] == '=') return argv[*i] + n + 1;
  if (argv[*i][n] != '\0') return NULL;
  if (*i + 1 >= argc) return "";
  return argv[++*i];
}
