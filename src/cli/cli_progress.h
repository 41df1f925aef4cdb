/* Progress of bake, verify and render: JSON lines on stdout for tools (the
 * Blender add-on reads {"event":"progress","stage":…,"done":…,"total":…}),
 * or a bar on stderr when it is a terminal, or nothing. */
#ifndef NBRDF_CLI_PROGRESS_H
#define NBRDF_CLI_PROGRESS_H

typedef struct cli_progress_state {
  int json, bar;
} cli_progress_state;

/* An nbrdf_progress_fn; `user` is a cli_progress_state. Never cancels (the
 * Ctrl-C flag of cli_cancel.h does). */
int cli_progress(void *user, const char *stage, double done, double total);

#endif
