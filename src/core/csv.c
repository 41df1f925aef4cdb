#include "core/csv.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"

/* Growable arrays double their capacity, so reading n bytes costs O(n). */
static int grow(void **data, size_t *cap, size_t need, size_t elem) {
  if (need <= *cap) return 1;
  size_t n = *cap ? *cap : 64;
  while (n < need)
    n *= 2;
  void *p = realloc(*data, n * elem);
  if (!p) return 0;
  *data = p;
  *cap = n;
  return 1;
}

static int is_blank(char c) { return c == ' ' || c == '\t'; }

void core_csv_free(core_csv_table *t) {
  if (!t) return;
  free(t->text);
  free(t->first_field);
  free(t->line);
  free(t->fields);
  memset(t, 0, sizeof *t);
}

/* Counts the physical lines of text[from..to), continuing *line and *line_len
 * (the bytes of the current line so far); 0 once a line exceeds CORE_CSV_LINE_MAX. */
static int lines_within_bound(const char *text, size_t from, size_t to, size_t *line,
                              size_t *line_len) {
  for (size_t i = from; i < to; i++) {
    if (text[i] == '\n') {
      ++*line;
      *line_len = 0;
    } else if (++*line_len > CORE_CSV_LINE_MAX + (text[i] == '\r')) {
      return 0; /* a CR before the LF is part of the line break */
    }
  }
  return 1;
}

static nbrdf_status line_too_long(nbrdf_error *err, const char *name, size_t line) {
  return core_fail(err, NBRDF_ERR_FORMAT, "%s: line %zu is longer than %d bytes (the limit)", name,
                   line, CORE_CSV_LINE_MAX);
}

nbrdf_status core_csv_read(FILE *in, const char *name, core_csv_table *table, nbrdf_error *err) {
  memset(table, 0, sizeof *table);
  char *buf = NULL;
  size_t len = 0, cap = 0, line = 1, line_len = 0;
  for (;;) {
    if (!grow((void **)&buf, &cap, len + 65536, 1)) {
      free(buf);
      return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory after %zu bytes", name, len);
    }
    size_t got = fread(buf + len, 1, cap - len, in);
    if (!lines_within_bound(buf, len, len + got, &line, &line_len)) {
      free(buf);
      return line_too_long(err, name, line);
    }
    len += got;
    if (got == 0) break;
  }
  if (ferror(in)) {
    free(buf);
    return core_fail(err, NBRDF_ERR_IO, "%s: read error after %zu bytes", name, len);
  }
  return core_csv_parse(buf, len, name, table, err);
}

typedef struct parser {
  core_csv_table *t;
  size_t cap_fields, cap_first, cap_line;
} parser;

static int push_field(parser *p, size_t start, size_t len) {
  core_csv_table *t = p->t;
  if (!grow((void **)&t->fields, &p->cap_fields, t->n_fields + 1, sizeof *t->fields)) return 0;
  t->fields[t->n_fields++] = (core_csv_span){start, len};
  return 1;
}

/* Opens record n_records (its end is fixed by the next call or by the final one). */
static int push_record(parser *p, size_t line) {
  core_csv_table *t = p->t;
  size_t need = t->n_records + 2;
  if (!grow((void **)&t->first_field, &p->cap_first, need, sizeof *t->first_field)) return 0;
  if (!grow((void **)&t->line, &p->cap_line, need, sizeof *t->line)) return 0;
  t->first_field[t->n_records] = t->n_fields;
  t->line[t->n_records] = line;
  t->n_records++;
  t->first_field[t->n_records] = t->n_fields;
  return 1;
}

nbrdf_status core_csv_parse(char *text, size_t len, const char *name, core_csv_table *table,
                            nbrdf_error *err) {
  memset(table, 0, sizeof *table);
  table->text = text;
  table->text_len = len;
  parser p = {table, 0, 0, 0};
  nbrdf_status st = NBRDF_OK;
  size_t pos = 0, line = 1, line_len = 0;
  if (!lines_within_bound(text, 0, len, &line, &line_len)) {
    st = line_too_long(err, name, line);
    goto fail;
  }
  line = 1;
  if (len >= 3 && !memcmp(text, "\xEF\xBB\xBF", 3)) pos = 3;
  if (!push_record(&p, 0)) goto oom; /* allocates first_field[0] for an empty input */
  table->n_records = 0;

  while (pos < len) {
    size_t q = pos;
    while (q < len && is_blank(text[q]))
      q++;
    if (q < len && text[q] == '\r' && (q + 1 == len || text[q + 1] == '\n')) q++;
    if (q == len || text[q] == '\n') { /* a blank line */
      pos = q + 1;
      line++;
      continue;
    }
    const size_t record_line = line;
    if (!push_record(&p, record_line)) goto oom;
    for (;;) {
      size_t start = pos, q2 = pos;
      while (q2 < len && is_blank(text[q2]))
        q2++;
      if (q2 < len && text[q2] == '"') {
        const size_t quote_line = line;
        for (q2++;; q2++) {
          if (q2 >= len) {
            st = core_fail(err, NBRDF_ERR_FORMAT, "line %zu: a quoted field is never closed",
                           quote_line);
            goto fail;
          }
          if (text[q2] == '\n') line++;
          if (text[q2] != '"') continue;
          if (q2 + 1 < len && text[q2 + 1] == '"') {
            q2++;
            continue;
          }
          q2++;
          break;
        }
        while (q2 < len && is_blank(text[q2]))
          q2++;
        if (q2 < len && text[q2] == '\r' && (q2 + 1 == len || text[q2 + 1] == '\n')) q2++;
        if (q2 < len && text[q2] != ',' && text[q2] != '\n') {
          st = core_fail(err, NBRDF_ERR_FORMAT, "line %zu: unexpected text after a closing quote",
                         line);
          goto fail;
        }
      } else {
        while (q2 < len && text[q2] != ',' && text[q2] != '\n')
          q2++;
      }
      size_t end = q2;
      if (end > start && text[end - 1] == '\r' && (q2 == len || text[q2] == '\n')) end--;
      if (!push_field(&p, start, end - start)) goto oom;
      table->first_field[table->n_records] = table->n_fields;
      if (q2 < len && text[q2] == ',') {
        pos = q2 + 1;
        continue;
      }
      pos = q2 < len ? q2 + 1 : q2;
      if (q2 < len) line++;
      break;
    }
  }
  return NBRDF_OK;

oom:
  st = core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory on line %zu", name, line);
fail:
  core_csv_free(table);
  return st;
}

size_t core_csv_value(const core_csv_table *t, size_t record, size_t column, char *buf,
                      size_t cap) {
  core_csv_span s = core_csv_field(t, record, column);
  const char *a = t->text + s.start, *b = a + s.len;
  while (a < b && is_blank(*a))
    a++;
  while (b > a && is_blank(b[-1]))
    b--;
  int quoted = b - a >= 2 && a[0] == '"' && b[-1] == '"';
  if (quoted) a++, b--;
  size_t n = 0;
  for (const char *c = a; c < b; c++) {
    if (quoted && c[0] == '"' && c + 1 < b && c[1] == '"') c++;
    if (n + 1 < cap) buf[n] = *c;
    n++;
  }
  if (cap) buf[n < cap ? n : cap - 1] = '\0';
  return n;
}

void core_csv_write_raw(FILE *out, const core_csv_table *t, size_t record, size_t column) {
  core_csv_span s = core_csv_field(t, record, column);
  fwrite(t->text + s.start, 1, s.len, out);
}
