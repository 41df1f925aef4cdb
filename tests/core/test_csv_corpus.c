/* Regression test over the minimised fuzzing corpus of the CSV reader
 * (tests/core/csv_corpus/, made by fuzz/fuzz_csv): every file parses into a
 * consistent table, the same in memory (core_csv_parse) and streamed (core_csv_read),
 * or is refused the same way by both, naming a line; every field's value
 * reads and parses as a number or is refused. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/csv.h"
#include "core/number.h"
#include "testing.h"

/* Returns 1 if the file parsed. */
static int replay(const char *path, const char *name) {
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  char *text = malloc(1 << 16);
  size_t len = fread(text, 1, 1 << 16, f);
  rewind(f);
  core_csv_table a, b;
  nbrdf_error ea = {0}, eb = {0};
  nbrdf_status sa = core_csv_parse(text, len, name, &a, &ea);
  nbrdf_status sb = core_csv_read(f, name, &b, &eb);
  fclose(f);
  CHECK_MSG((sa == NBRDF_OK) == (sb == NBRDF_OK), "%s: parse %s, read %s", name,
            nbrdf_status_name(sa), nbrdf_status_name(sb));
  if (sa != NBRDF_OK) {
    CHECK_MSG(strstr(ea.message, "line ") && !strcmp(ea.message, eb.message), "%s: \"%s\" / \"%s\"",
              name, ea.message, eb.message);
  } else if (sb == NBRDF_OK) {
    CHECK_MSG(a.n_records == b.n_records && a.n_fields == b.n_fields, "%s: tables differ", name);
    for (size_t r = 0; r < a.n_records; r++) {
      CHECK(a.line[r] >= 1 && (r == 0 || a.line[r] >= a.line[r - 1]));
      for (size_t c = 0; c < core_csv_record_width(&a, r); c++) {
        core_csv_span s = core_csv_field(&a, r, c);
        CHECK(s.start + s.len <= a.text_len);
        char buf[256];
        size_t n = core_csv_value(&a, r, c, buf, sizeof buf);
        double x;
        if (n < sizeof buf && core_parse_number(buf, n, &x) == NBRDF_NUMBER_OK)
          CHECK_MSG(isfinite(x), "%s: '%s' read as %g", name, buf, x);
      }
    }
  }
  core_csv_free(&a);
  core_csv_free(&b);
  return sa == NBRDF_OK;
}

static void test_corpus(void) {
  char dir[512];
  snprintf(dir, sizeof dir, "%s/tests/core/csv_corpus", testing_source_dir());
  size_t n = 0;
  char **names = testing_list_dir(dir, &n); /* sorted: a stable order for the log */
  if (!names) return;
  int parsed = 0;
  for (size_t i = 0; i < n; i++) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    parsed += replay(path, names[i]);
    free(names[i]);
  }
  free(names);
  printf("corpus: %zu files, %d parsed, %zu refused\n", n, parsed, n - (size_t)parsed);
  CHECK(n >= 10);
  CHECK(parsed > 0 && (size_t)parsed < n);
}

int main(void) {
  RUN(test_corpus);
  return testing_finish();
}
