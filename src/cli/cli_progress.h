/* Progress of every long command, one callback for all (docs/CLI.md, "Progress"). With
 * --progress=json: JSON lines on stdout, one format for all of them (the Blender add-on
 * reads it):
 *   {"event":"progress","stage":…,"done":…,"total":…[,"seconds":…,"rate":…,"eta_s":…]}
 * Other stdout lines of the command (its summary, "done" events) are separate lines; a tool
 * keeps the lines that parse as JSON. Without the flag: text on stderr, in the command's
 * style. Every style stops the work on Ctrl-C (SIGINT, SIGTERM, SIGHUP) once
 * cli_cancel_watch() is active. */
#ifndef NBRDF_CLI_PROGRESS_H
#define NBRDF_CLI_PROGRESS_H

#include <stdio.h>

#include "cli/cli_options.h"
#include "nbrdf/status.h"

/* The styles differ where the commands' work does: */
typedef enum cli_progress_style {
  /* bake, render, verify: a bar on a terminal (nothing when stderr is not one); a line at
   * every call, which the library's ticker keeps to ~10 a second. */
  CLI_PROGRESS_BAR,
  /* train, evaluate: "\r<stage>: done/total (p %)", at most a line a second and the last. */
  CLI_PROGRESS_COUNT,
  /* dataset (runs of hours, resumed): a line a second at most with this run's rate and the
   * ETA, in text and in the JSON lines (seconds, rate, eta_s). */
  CLI_PROGRESS_RATE
} cli_progress_style;

typedef struct cli_progress_state {
  cli_progress_style style;
  const char *unit; /* RATE: what `done` counts, for the text ("BRDFs") */
  int json;         /* --progress=json */
  int bar;          /* BAR on a terminal, without json (cli_progress_start) */
  /* monotonic seconds of cli_progress_start; `done` at the first call (a resumed run's
   * rate is its own); seconds after start of the last line (< 0: none yet) */
  double start, first_done, last_line;
} cli_progress_state;

cli_progress_state cli_progress_init(cli_progress_style style, const char *unit);
/* The --progress=json option's table entry (cli_options.h), `state` a cli_progress_state *
 * and `text` its help line. */
extern const int cli_progress_json_value[1];
#define CLI_PROGRESS_OPTION(state, text)                                                           \
  {                                                                                                \
    .type = CLI_OPT_ENUM, .name = "--progress", .dest = &(state)->json, .choices = "json",         \
    .values = cli_progress_json_value, .help = text                                                \
  }
/* Starts the clock (seconds, rate) and decides the bar; call just before the work. */
void cli_progress_start(cli_progress_state *p);
/* Seconds since cli_progress_start. */
double cli_progress_seconds(const cli_progress_state *p);

/* An nbrdf_progress_fn; `user` is a cli_progress_state. Returns the Ctrl-C flag of
 * cli_cancel.h, so that calls without a cancel flag of their own stop too. */
int cli_progress(void *user, const char *stage, double done, double total);

/* One progress line in the shared JSON format on stdout, flushed. `seconds` < 0 leaves out
 * the timing fields: seconds since start, `rate` in units of `done` per second (this run's,
 * so a resumed run's own), eta_s (-1 when unknown). */
void cli_progress_json(const char *stage, double done, double total, double seconds, double rate);
/* The same line without timing, `fields` (",\"tile\":1003", say: JSON members, each led by a
 * comma) added at its end: where one run holds several works (the tiles of a set). */
void cli_progress_json_fields(const char *stage, double done, double total, const char *fields);

/* `text` as a JSON string on `out` (control characters dropped). */
void cli_json_string(FILE *out, const char *text);

/* The end of a command whose library call failed with `st`: the maps' advice in the options'
 * words (cli_params_explain), the bar's line ended, a JSON error event, and the message
 * ("cancelled; no file written" for a cancel). Returns CLI_EXIT_FAILURE. */
int cli_progress_fail(const char *cmd, nbrdf_status st, nbrdf_error *err,
                      const cli_progress_state *ps);

#endif
