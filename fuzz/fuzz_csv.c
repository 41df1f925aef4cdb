/* libFuzzer target for the CSV reader of `nbrdf eval` (src/core/csv.c) and
 * the number parser its fields go through (src/core/number.c).
 *
 * Properties checked on every input, beyond "no crash, no sanitizer report":
 * - core_csv_parse (in memory) and core_csv_read (streamed, through fmemopen) agree:
 *   both accept, with the same records and fields, or both refuse;
 * - a refusal leaves the table empty and says which line, and a line longer
 *   than CORE_CSV_LINE_MAX is always refused;
 * - an accepted table is consistent: field spans inside the text, records'
 *   fields contiguous and in order, line numbers >= 1 and non-decreasing,
 *   no record on a blank line;
 * - every field's value reads (core_csv_value, into a small and a large buffer,
 *   same length) and parses as a number or is refused; a number accepted is
 *   finite and a re-parse of its printed form gives it back.
 *
 * Build and run: see fuzz/README.md. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/csv.h"
#include "core/number.h"

#define REQUIRE(cond)                                                                              \
  do {                                                                                             \
    if (!(cond)) abort();                                                                          \
  } while (0)

static int has_long_line(const uint8_t *d, size_t n) {
  size_t run = 0;
  for (size_t i = 0; i < n; i++) {
    if (d[i] == '\n') {
      run = 0;
      continue;
    }
    run++;
    int cr_before_lf = d[i] == '\r' && i + 1 < n && d[i + 1] == '\n';
    if (run > CORE_CSV_LINE_MAX + (size_t)cr_before_lf) return 1;
  }
  return 0;
}

static void check_value(const core_csv_table *t, size_t r, size_t c) {
  char small[8], big[256];
  size_t n1 = core_csv_value(t, r, c, small, sizeof small);
  size_t n2 = core_csv_value(t, r, c, big, sizeof big);
  REQUIRE(n1 == n2);
  /* <=: a value may hold a NUL byte */
  REQUIRE(strlen(small) <= (n1 < sizeof small ? n1 : sizeof small - 1));
  REQUIRE(memcmp(small, big, n1 < sizeof small ? n1 : sizeof small - 1) == 0);
  if (n2 >= sizeof big) return;
  double x = 0;
  core_number_result nr = core_parse_number(big, n2, &x);
  REQUIRE(nr >= NBRDF_NUMBER_OK && nr <= NBRDF_NUMBER_UNDERFLOW);
  REQUIRE(core_number_problem(nr) != NULL);
  if (nr != NBRDF_NUMBER_OK) return;
  REQUIRE(isfinite(x));
  char again[64];
  snprintf(again, sizeof again, "%.17g", x);
  double y = 1;
  REQUIRE(core_parse_number(again, strlen(again), &y) == NBRDF_NUMBER_OK && y == x);
}

static void check_table(const core_csv_table *t) {
  REQUIRE(t->n_records == 0 || t->first_field[0] == 0);
  size_t prev_line = 1;
  for (size_t r = 0; r < t->n_records; r++) {
    REQUIRE(t->first_field[r] <= t->first_field[r + 1]);
    REQUIRE(core_csv_record_width(t, r) >= 1);
    REQUIRE(t->line[r] >= prev_line);
    prev_line = t->line[r];
    for (size_t c = 0; c < core_csv_record_width(t, r); c++) {
      core_csv_span s = core_csv_field(t, r, c);
      REQUIRE(s.start <= t->text_len && s.len <= t->text_len - s.start);
      check_value(t, r, c);
    }
  }
  REQUIRE(t->n_records == 0 || t->first_field[t->n_records] == t->n_fields);
}

static int same_tables(const core_csv_table *a, const core_csv_table *b) {
  if (a->n_records != b->n_records || a->n_fields != b->n_fields) return 0;
  for (size_t r = 0; r < a->n_records; r++)
    if (a->line[r] != b->line[r] || a->first_field[r] != b->first_field[r]) return 0;
  for (size_t f = 0; f < a->n_fields; f++)
    if (a->fields[f].start != b->fields[f].start || a->fields[f].len != b->fields[f].len) return 0;
  return 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char *text = malloc(size ? size : 1);
  REQUIRE(text != NULL);
  memcpy(text, data, size);
  core_csv_table a, b;
  nbrdf_error ea = {0}, eb = {0};
  nbrdf_status sa = core_csv_parse(text, size, "fuzz", &a, &ea);
  if (sa == NBRDF_OK) {
    REQUIRE(!has_long_line(data, size));
    check_table(&a);
  } else {
    REQUIRE(a.n_records == 0 && a.text == NULL && a.fields == NULL);
    REQUIRE(strstr(ea.message, "line ") != NULL);
  }
  if (size > 0) {
    FILE *f = fmemopen((void *)data, size, "rb");
    REQUIRE(f != NULL);
    nbrdf_status sb = core_csv_read(f, "fuzz", &b, &eb);
    fclose(f);
    REQUIRE((sa == NBRDF_OK) == (sb == NBRDF_OK));
    if (sb == NBRDF_OK)
      REQUIRE(same_tables(&a, &b));
    else
      REQUIRE(!strcmp(ea.message, eb.message) || sa == NBRDF_ERR_MEMORY || sb == NBRDF_ERR_MEMORY);
    core_csv_free(&b);
  }
  core_csv_free(&a);
  return 0;
}
