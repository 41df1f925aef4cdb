#include "cli/cli_progress.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli_cancel.h"
#include "cli/cli_common.h"
#include "cli/cli_params.h"
#include "core/progress.h"

cli_progress_state cli_progress_init(cli_progress_style style, const char *unit) {
  cli_progress_state p = {style, unit, 0, 0, 0.0, -1.0, -1.0};
  return p;
}

const int cli_progress_json_value[1] = {1};

void cli_progress_start(cli_progress_state *p) {
  p->bar = p->style == CLI_PROGRESS_BAR && !p->json && isatty(STDERR_FILENO);
  p->start = core_monotonic_seconds();
  p->first_done = -1.0, p->last_line = -1.0;
}

double cli_progress_seconds(const cli_progress_state *p) {
  return core_monotonic_seconds() - p->start;
}

static void json_line(const char *stage, double done, double total, double seconds, double rate,
                      const char *fields) {
  /* done moves within a band / texel: fractional, two decimals */
  printf("{\"event\":\"progress\",\"stage\":\"%s\",\"done\":%.*f,\"total\":%.0f", stage,
         done == (double)(long long)done ? 0 : 2, done, total);
  if (seconds >= 0) {
    double eta = rate > 0 ? (total - done) / rate : -1.0;
    printf(",\"seconds\":%.2f,\"rate\":%.4g,\"eta_s\":%.0f", seconds, rate, eta);
  }
  fputs(fields, stdout);
  fputs("}\n", stdout);
  fflush(stdout);
}

void cli_progress_json(const char *stage, double done, double total, double seconds, double rate) {
  json_line(stage, done, total, seconds, rate, "");
}

void cli_progress_json_fields(const char *stage, double done, double total, const char *fields) {
  json_line(stage, done, total, -1.0, 0.0, fields);
}

static void bar(const char *stage, double done, double total) {
  int width = 40, filled = total > 0 ? (int)(width * done / total) : width;
  fprintf(stderr, "\r%s [", stage);
  for (int i = 0; i < width; i++)
    fputc(i < filled ? '#' : ' ', stderr);
  fprintf(stderr, "] %3.0f%%", total > 0 ? 100.0 * done / total : 100.0);
  if (done >= total) fputc('\n', stderr);
  fflush(stderr);
}

int cli_progress(void *user, const char *stage, double done, double total) {
  cli_progress_state *p = user;
  double t = cli_progress_seconds(p);
  if (p->first_done < 0) p->first_done = done;
  /* Text read by a person (and a log's lines): one a second is enough. */
  if (p->style != CLI_PROGRESS_BAR && done < total && p->last_line >= 0 && t - p->last_line < 1.0)
    return *cli_cancel_flag();
  p->last_line = t;
  double rate = t > 0 ? (done - p->first_done) / t : 0.0;
  if (p->json) {
    cli_progress_json(stage, done, total, p->style == CLI_PROGRESS_RATE ? t : -1.0, rate);
  } else if (p->style == CLI_PROGRESS_BAR) {
    if (p->bar) bar(stage, done, total);
  } else if (p->style == CLI_PROGRESS_COUNT) {
    fprintf(stderr, "\r%s: %.0f/%.0f (%.1f %%)  ", stage, done, total, 100.0 * done / total);
  } else {
    fprintf(stderr, "%s: %.0f/%.0f %s (%.1f %%), %.3g %s/s, ETA %.0f s\n", stage, done, total,
            p->unit, 100.0 * done / total, rate, p->unit, rate > 0 ? (total - done) / rate : -1.0);
  }
  return *cli_cancel_flag();
}

void cli_json_string(FILE *out, const char *text) {
  fputc('"', out);
  for (const char *c = text; *c; c++)
    if (*c == '"' || *c == '\\')
      fprintf(out, "\\%c", *c);
    else if ((unsigned char)*c >= 0x20)
      fputc(*c, out);
  fputc('"', out);
}

int cli_progress_fail(const char *cmd, nbrdf_status st, nbrdf_error *err,
                      const cli_progress_state *ps) {
  cli_params_explain(err);
  if (ps->bar) fputc('\n', stderr);
  if (ps->json) {
    printf("{\"event\":\"error\",\"status\":\"%s\",\"message\":", nbrdf_status_name(st));
    cli_json_string(stdout, err->message);
    printf("}\n");
  }
  if (st == NBRDF_ERR_CANCELLED)
    return cli_fail(cmd, "%s: cancelled; no file written", cli_cancel_reason());
  return cli_fail_error(cmd, err);
}
