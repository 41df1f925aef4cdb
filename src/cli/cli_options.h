/* Every command's options as one declarative table (docs/CLI.md, "Options"): the parser,
 * the command's --help and `nbrdf completion` all read the same table, so an option cannot
 * be parsed without being documented and completed, nor the other way round.
 *
 * Syntax, the same for every command: `--name value` or `--name=value` (an alias such as
 * `-o` takes its value as the next argument); a flag takes no value; `--` ends the options;
 * any other argument not starting with '-' (or exactly "-") is positional. A value is never
 * empty. Errors are usage errors naming the command, the option and what was expected:
 *   nbrdf bake: --tile expects an integer in [8, 1024], got 'abc'
 */
#ifndef NBRDF_CLI_OPTIONS_H
#define NBRDF_CLI_OPTIONS_H

#include <stdint.h>
#include <stdio.h>

typedef enum cli_opt_type {
  CLI_OPT_END = 0, /* the table's end; with `help` set and no name: a section heading */
  CLI_OPT_FLAG,    /* no value: *(int *)dest = value */
  CLI_OPT_INT,     /* an integer in [lo, hi] -> *(int *)dest */
  CLI_OPT_U64,     /* decimal digits, at least lo, at most hi when hi > 0 -> *(uint64_t *)dest */
  CLI_OPT_DOUBLE,  /* a number in [lo, hi] -> *(double *)dest */
  CLI_OPT_FLOAT,   /* the same, kept as a float -> *(float *)dest */
  CLI_OPT_STRING,  /* any text -> *(const char **)dest */
  CLI_OPT_PATH,    /* a file or folder -> *(const char **)dest; completed as a path */
  CLI_OPT_ENUM,    /* one of `choices` ("a|b|c") -> *(int *)dest = values[k], or k */
  CLI_OPT_CUSTOM,  /* parse() reads the value (colour constants, WxH, lists, ...) */
} cli_opt_type;

typedef struct cli_opt cli_opt;
/* A custom value's reader: returns 0 when accepted, else prints its usage error (with
 * cli_opt_bad, say) and returns non-zero. */
typedef int (*cli_opt_parse_fn)(const char *cmd, const cli_opt *o, const char *value);

struct cli_opt {
  cli_opt_type type;
  const char *name;    /* "--spp" */
  const char *meta;    /* the value in help: "N", "FILE" (default: the choices, else VALUE) */
  const char *help;    /* help text; '\n' starts a continuation line */
  void *dest;          /* where the value goes (see the types) */
  double lo, hi;       /* INT, DOUBLE, FLOAT, U64: the closed range (U64: hi 0, no cap) */
  const char *choices; /* ENUM: "none|bilinear"; CUSTOM: words completion offers */
  const int *values;   /* ENUM: the value of each choice (NULL: its index) */
  int value;           /* FLAG: what is stored; CUSTOM: free for the reader (an id) */
  cli_opt_parse_fn parse;
  const char *alias; /* "-o" */
  int *seen;         /* incremented at each occurrence (NULL: not counted); given twice, an
                        option's last value counts unless its reader says otherwise */
};

/* The result of cli_options_parse besides CLI_EXIT_USAGE. */
enum { CLI_OPTIONS_OK = 0, CLI_OPTIONS_HELP = -1 };

typedef struct cli_positionals {
  const char **value; /* receives the positional arguments in order */
  int max;            /* how many the command takes */
  int count;          /* how many were given */
  const char *meta;   /* "TEXTURE.exr", for the error of one too many */
} cli_positionals;

/* Parses argv[first..argc) against `table` (ended by CLI_OPT_END with no help), the
 * positional arguments into `pos` (NULL: none taken). Returns CLI_OPTIONS_OK, CLI_OPTIONS_HELP
 * when -h/--help was given (nothing printed), or CLI_EXIT_USAGE after printing the error. */
int cli_options_parse(const char *cmd, const cli_opt *table, int argc, char **argv, int first,
                      cli_positionals *pos);

/* "nbrdf CMD: OPTION expects WHAT, got 'VALUE'" (and the hint): returns CLI_EXIT_USAGE. */
int cli_opt_bad(const char *cmd, const char *option, const char *what, const char *value);

/* `v` as people write it, for messages: %g without '+' or leading zeros in the exponent
 * (1e9, 1e-6, 0.25). */
const char *cli_opt_number(double v, char *buf, size_t cap);

/* Prints the table's help: one entry per option, its help aligned at column 24, section
 * headings as they come. */
void cli_options_help(FILE *out, const cli_opt *table);

/* What a shell completes as the option's value: "" (a flag: nothing), "f" (a path), "w" and
 * the words of `choices` separated by spaces ("w alpha perceptual"), or "v" (any value). */
const char *cli_opt_completion(const cli_opt *o, char *buf, size_t cap);

/* A command's tables, for help and completion without running it: the command builds each
 * table (of its subcommand `sub`, or NULL) with destinations of its own and shows it to the
 * visitor, which must not keep it. */
typedef void (*cli_opt_visit)(void *user, const char *sub, const cli_opt *table);

/* Visitors for a command's options(): parse argv with each table shown (`user` a
 * cli_parse_call; the tables of subcommands other than its `sub` are skipped), and print
 * each table's help (`user` the FILE *). */
typedef struct cli_parse_call {
  const char *cmd, *sub;
  int argc, first;
  char **argv;
  cli_positionals *pos;
  int rc; /* cli_options_parse's result */
} cli_parse_call;
void cli_options_parse_visit(void *user, const char *sub, const cli_opt *table);
void cli_options_help_visit(void *user, const char *sub, const cli_opt *table);

#endif
