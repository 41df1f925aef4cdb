#include "train/run_log.h"

#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

/* Reads the rows of an existing log with step <= keep (header excluded). */
static char *kept_rows(const char *path, int64_t keep) {
  FILE *f = fopen(path, "r");
  if (!f) return NULL;
  size_t cap = 4096, len = 0;
  char *out = malloc(cap), line[1024];
  int first = 1;
  while (out && fgets(line, sizeof line, f)) {
    if (first) {
      first = 0;
      continue;
    }
    char *end;
    long long step = strtoll(line, &end, 10);
    if (end == line || step > keep) continue;
    size_t n = strlen(line);
    if (len + n + 1 > cap) {
      char *p = realloc(out, cap = 2 * (len + n + 1));
      if (!p) {
        free(out);
        out = NULL;
        break;
      }
      out = p;
    }
    memcpy(out + len, line, n);
    len += n;
  }
  if (out) out[len] = '\0';
  fclose(f);
  return out;
}

nbrdf_status run_log_open(run_log *log, const char *path, const char *header, int64_t keep_to_step,
                          nbrdf_error *err) {
  char *rows = keep_to_step > 0 ? kept_rows(path, keep_to_step) : NULL;
  log->f = fopen(path, "w");
  if (!log->f) {
    free(rows);
    return nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot write the log: %s", path, strerror(errno));
  }
  fprintf(log->f, "%s\n%s", header, rows ? rows : "");
  fflush(log->f);
  free(rows);
  return NBRDF_OK;
}

void run_log_row(run_log *log, const char *fmt, ...) {
  if (!log->f) return;
  va_list ap;
  va_start(ap, fmt);
  vfprintf(log->f, fmt, ap);
  va_end(ap);
  fputc('\n', log->f);
  fflush(log->f);
}

void run_log_close(run_log *log) {
  if (log->f) fclose(log->f);
  log->f = NULL;
}
