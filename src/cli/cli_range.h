/* The bake's range report on the command line (docs/CLI.md, "Range report"): one line on
 * stderr per parameter outside the model's trained range, and with --progress=json one
 * {"event":"range",...} line on stdout each, before any progress. */
#ifndef NBRDF_CLI_RANGE_H
#define NBRDF_CLI_RANGE_H

#include "nbrdf/bake.h"

/* An nbrdf_bake_options.range_report; `user` is the command's cli_progress_state. */
void cli_range_report(void *user, const nbrdf_bake_range *range);

#endif
