/* Progress of every long command. With --progress=json: JSON lines on stdout, one format
 * for all of them (the Blender add-on reads it):
 *   {"event":"progress","stage":…,"done":…,"total":…[,"seconds":…,"rate":…,"eta_s":…]}
 * Other stdout lines of the command (its summary, "done" events) are separate lines; a tool
 * keeps the lines that parse as JSON. Without the flag: a bar or text lines on stderr. */
#ifndef NBRDF_CLI_PROGRESS_H
#define NBRDF_CLI_PROGRESS_H

typedef struct cli_progress_state {
  int json, bar;
} cli_progress_state;

/* An nbrdf_progress_fn; `user` is a cli_progress_state. Never cancels (the
 * Ctrl-C flag of cli_cancel.h does). */
int cli_progress(void *user, const char *stage, double done, double total);

/* One progress line in the shared JSON format on stdout, flushed. `seconds` < 0 leaves out
 * the timing fields: seconds since start, `rate` in units of `done` per second (this run's,
 * so a resumed run's own), eta_s (-1 when unknown). */
void cli_progress_json(const char *stage, double done, double total, double seconds, double rate);

#endif
