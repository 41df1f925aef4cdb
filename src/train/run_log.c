#include "train/run_log.h"

#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error.h"
#include "core/output_file.h"

/* Reads the rows of an existing log with step <= keep (header excluded). */
static char *kept_rows(const char *path, int64_t keep) {
  /* Only a regular file is read: a FIFO would block here (the write that
   * follows refuses any other kind of file with a message). */
  struct stat sb;
  if (stat(path, &sb) != 0 || !S_ISREG(sb.st_mode)) return NULL;
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

nbrdf_status train_run_log_open(train_run_log *log, const char *path, const char *header,
                                int64_t keep_to_step, nbrdf_error *err) {
  log->f = NULL;
  char *rows = keep_to_step > 0 ? kept_rows(path, keep_to_step) : NULL;
  size_t n = strlen(header) + 2 + (rows ? strlen(rows) : 0);
  char *text = malloc(n);
  if (!text) {
    free(rows);
    return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  }
  snprintf(text, n, "%s\n%s", header, rows ? rows : "");
  free(rows);
  /* The kept rows replace the log whole (core/output_file.h); later rows are appended. */
  nbrdf_status st = core_output_file_write_all(path, text, strlen(text), NULL, 0, err);
  free(text);
  if (st != NBRDF_OK) return st;
  log->f = fopen(path, "a");
  if (!log->f)
    return core_fail(err, NBRDF_ERR_IO, "%s: cannot append to the log: %s", path, strerror(errno));
  return NBRDF_OK;
}

void train_run_log_row(train_run_log *log, const char *fmt, va_list ap) {
  if (!log->f) return;
  vfprintf(log->f, fmt, ap);
  fputc('\n', log->f);
  fflush(log->f);
}

void train_run_log_close(train_run_log *log) {
  if (log->f) fclose(log->f);
  log->f = NULL;
}
