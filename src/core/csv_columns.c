#include "core/csv_columns.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "core/number.h"

nbrdf_status core_csv_columns_find(const core_csv_table *t, const char *name,
                                   const core_csv_column *const *cols, int n,
                                   const char *const *reserved, const char *needs, size_t *index,
                                   nbrdf_error *err) {
  size_t width = core_csv_record_width(t, 0);
  char field[64];
  for (int c = 0; c < n; c++)
    index[c] = width;
  for (size_t k = 0; k < width; k++) {
    core_csv_value(t, 0, k, field, sizeof field);
    for (int o = 0; reserved && reserved[o]; o++)
      if (!strcmp(field, reserved[o]))
        return core_fail(err, NBRDF_ERR_FORMAT, "%s:%zu: the input already has a column '%s'", name,
                         t->line[0], field);
    for (int c = 0; c < n; c++) {
      if (strcmp(field, cols[c]->name)) continue;
      if (index[c] != width)
        return core_fail(err, NBRDF_ERR_FORMAT, "%s:%zu: column '%s' appears twice", name,
                         t->line[0], field);
      index[c] = k;
    }
  }
  for (int c = 0; c < n; c++)
    if (index[c] == width)
      return core_fail(err, NBRDF_ERR_FORMAT, "%s:%zu: missing column '%s' (%s)", name, t->line[0],
                       cols[c]->name, needs);
  return NBRDF_OK;
}

/* A field's text made safe and short for a message. */
static const char *printable(const char *s, char *buf, size_t cap) {
  size_t n = 0;
  for (; *s && n + 4 < cap; s++)
    buf[n++] = (*s >= 32 && *s < 127) ? *s : '?';
  if (*s) buf[n++] = '.', buf[n++] = '.', buf[n++] = '.';
  buf[n] = '\0';
  return buf;
}

static const char *range_text(const core_csv_column *c, char *buf, size_t cap) {
  if (isinf(c->lo) && isinf(c->hi))
    snprintf(buf, cap, "a number");
  else
    snprintf(buf, cap, "a number in [%g, %g%c", c->lo, c->hi, c->hi_open ? ')' : ']');
  return buf;
}

nbrdf_status core_csv_columns_read(const core_csv_table *t, const char *name, size_t r,
                                   const core_csv_column *const *cols, const size_t *index, int n,
                                   double *v, nbrdf_error *err) {
  size_t width = core_csv_record_width(t, r), want = core_csv_record_width(t, 0);
  if (width != want)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s:%zu: %zu fields, but the header has %zu columns",
                     name, t->line[r], width, want);
  char buf[128], shown[64], range[96];
  for (int c = 0; c < n; c++) {
    const core_csv_column *s = cols[c];
    size_t len = core_csv_value(t, r, index[c], buf, sizeof buf);
    if (len == 0)
      return core_fail(err, NBRDF_ERR_FORMAT, "%s:%zu: column '%s' expects %s, got nothing", name,
                       t->line[r], s->name, range_text(s, range, sizeof range));
    double x = 0;
    /* A value longer than the buffer, or holding a NUL byte, is no number. */
    core_number_result nr = len < sizeof buf && strlen(buf) == len ? core_parse_number(buf, len, &x)
                                                                   : NBRDF_NUMBER_SYNTAX;
    int out = nr == NBRDF_NUMBER_OK && (x < s->lo || x > s->hi || (s->hi_open && x == s->hi));
    if (nr != NBRDF_NUMBER_OK || out)
      return core_fail(
          err, NBRDF_ERR_FORMAT, "%s:%zu: column '%s' expects %s, got '%s'%s%s", name, t->line[r],
          s->name, range_text(s, range, sizeof range), printable(buf, shown, sizeof shown),
          nr == NBRDF_NUMBER_OVERFLOW || nr == NBRDF_NUMBER_UNDERFLOW ? ", which " : "",
          nr == NBRDF_NUMBER_OVERFLOW || nr == NBRDF_NUMBER_UNDERFLOW ? core_number_problem(nr)
                                                                      : "");
    v[c] = x;
  }
  return NBRDF_OK;
}
