/* A small CSV reader for the CLI's point queries (`nbrdf eval`).
 *
 * Records are separated by LF or CRLF; fields by commas. A field that starts
 * with '"' is quoted (RFC 4180): it may hold commas, newlines and doubled
 * quotes. Each field keeps its raw text (quotes and surrounding spaces
 * included) so that columns the caller does not interpret can be written back
 * byte for byte. Blank lines (empty or only spaces/tabs) are skipped wherever
 * they are; a UTF-8 byte-order mark before the header is dropped. Line numbers
 * are physical lines of the input, counted from 1 (the header's line); parse
 * errors name the line and leave `name` (the input's name) to I/O errors.
 *
 * A physical line holds at most CORE_CSV_LINE_MAX bytes (its line break excluded):
 * a longer one is refused, naming it, as soon as it has been read that far,
 * so that a stream without line breaks (`< /dev/zero`) cannot grow memory
 * without bound. */
#ifndef NBRDF_CORE_CSV_H
#define NBRDF_CORE_CSV_H

#include <stddef.h>
#include <stdio.h>

#include "nbrdf/status.h"

#define CORE_CSV_LINE_MAX 65536

typedef struct core_csv_span {
  size_t start; /* offset into core_csv_table.text */
  size_t len;
} core_csv_span;

typedef struct core_csv_table {
  char *text; /* the whole input, owned */
  size_t text_len;
  size_t n_records;    /* header included; 0 for an empty input */
  size_t *first_field; /* record r has fields first_field[r] .. first_field[r + 1] - 1 */
  size_t *line;        /* record r starts on this physical line */
  core_csv_span *fields;
  size_t n_fields;
} core_csv_table;

/* Reads `in` to its end and splits it into records. `name` ("stdin") prefixes
 * error messages. On failure the table is left empty (core_csv_free is harmless). */
nbrdf_status core_csv_read(FILE *in, const char *name, core_csv_table *table, nbrdf_error *err);

/* Splits text[0..len) (taking ownership of `text`, which must come from malloc). */
nbrdf_status core_csv_parse(char *text, size_t len, const char *name, core_csv_table *table,
                            nbrdf_error *err);

void core_csv_free(core_csv_table *table);

static inline size_t core_csv_record_width(const core_csv_table *t, size_t record) {
  return t->first_field[record + 1] - t->first_field[record];
}

static inline core_csv_span core_csv_field(const core_csv_table *t, size_t record, size_t column) {
  return t->fields[t->first_field[record] + column];
}

/* The field's value: quotes removed ("" -> "), leading and trailing spaces and
 * tabs trimmed, NUL-terminated in `buf` (cap bytes). Returns the value's
 * length, which may exceed cap - 1 (the copy is then truncated). */
size_t core_csv_value(const core_csv_table *t, size_t record, size_t column, char *buf, size_t cap);

/* Writes a field's raw text unchanged. */
void core_csv_write_raw(FILE *out, const core_csv_table *t, size_t record, size_t column);

#endif
