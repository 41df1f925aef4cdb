/* core/csv_columns.h: numeric columns found by name and read with range checks, one message
 * style ("NAME:LINE: column 'x' expects a number in [lo, hi], got '...'"). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/csv_columns.h"
#include "testing.h"

static const core_csv_column ALPHA = {"alpha", 0.001, 1, 0}, THETA = {"theta", 0, 90, 1},
                             ANY = {"x", -INFINITY, INFINITY, 0};
static const core_csv_column *const COLS[3] = {&ALPHA, &THETA, &ANY};
static const char *const RESERVED[] = {"f", NULL};

static void parse(const char *text, core_csv_table *t) {
  nbrdf_error err = {0};
  char *copy = malloc(strlen(text) + 1);
  memcpy(copy, text, strlen(text) + 1);
  CHECK_OK(core_csv_parse(copy, strlen(text), "q.csv", t, &err), &err);
}

static void test_find(void) {
  core_csv_table t;
  nbrdf_error err = {0};
  size_t index[3];
  parse("note,x,theta,alpha\n", &t);
  CHECK_OK(core_csv_columns_find(&t, "q.csv", COLS, 3, RESERVED, "needs", index, &err), &err);
  CHECK(index[0] == 3 && index[1] == 2 && index[2] == 1);
  core_csv_free(&t);

  parse("alpha,theta\n", &t);
  CHECK_FAILS(
      core_csv_columns_find(&t, "q.csv", COLS, 3, RESERVED, "model m needs alpha,x", index, &err),
      NBRDF_ERR_FORMAT, &err, "q.csv:1: missing column 'x' (model m needs alpha,x)");
  core_csv_free(&t);
  parse("\nalpha,theta,alpha,x\n", &t);
  CHECK_FAILS(core_csv_columns_find(&t, "q.csv", COLS, 3, NULL, "", index, &err), NBRDF_ERR_FORMAT,
              &err, "q.csv:2: column 'alpha' appears twice");
  core_csv_free(&t);
  parse("alpha,theta,x,f\n", &t);
  CHECK_FAILS(core_csv_columns_find(&t, "q.csv", COLS, 3, RESERVED, "", index, &err),
              NBRDF_ERR_FORMAT, &err, "q.csv:1: the input already has a column 'f'");
  core_csv_free(&t);
}

static void test_read(void) {
  core_csv_table t;
  nbrdf_error err = {0};
  size_t index[3] = {0, 1, 2};
  double v[3];
  parse("alpha,theta,x\n"
        "0.5, 89.5 ,-1e300\n"
        "\"1\",0,0\n"
        "2,0,0\n"
        "0.5,90,0\n"
        "0.5,abc,0\n"
        "0.5,,0\n"
        "0.5,0\n"
        "0.5,0,1e400\n"
        "0.0001,0,0\n",
        &t);
  CHECK_OK(core_csv_columns_read(&t, "stdin", 1, COLS, index, 3, v, &err), &err);
  CHECK(v[0] == 0.5 && v[1] == 89.5 && v[2] == -1e300);
  CHECK_OK(core_csv_columns_read(&t, "stdin", 2, COLS, index, 3, v, &err), &err);
  CHECK(v[0] == 1 && v[1] == 0);
  CHECK_FAILS(core_csv_columns_read(&t, "stdin", 3, COLS, index, 3, v, &err), NBRDF_ERR_FORMAT,
              &err, "stdin:4: column 'alpha' expects a number in [0.001, 1], got '2'");
  CHECK_FAILS(core_csv_columns_read(&t, "stdin", 4, COLS, index, 3, v, &err), NBRDF_ERR_FORMAT,
              &err, "stdin:5: column 'theta' expects a number in [0, 90), got '90'");
  CHECK_FAILS(core_csv_columns_read(&t, "stdin", 5, COLS, index, 3, v, &err), NBRDF_ERR_FORMAT,
              &err, "stdin:6: column 'theta' expects a number in [0, 90), got 'abc'");
  CHECK_FAILS(core_csv_columns_read(&t, "stdin", 6, COLS, index, 3, v, &err), NBRDF_ERR_FORMAT,
              &err, "stdin:7: column 'theta' expects a number in [0, 90), got nothing");
  CHECK_FAILS(core_csv_columns_read(&t, "stdin", 7, COLS, index, 3, v, &err), NBRDF_ERR_FORMAT,
              &err, "stdin:8: 2 fields, but the header has 3 columns");
  CHECK_FAILS(core_csv_columns_read(&t, "stdin", 8, COLS, index, 3, v, &err), NBRDF_ERR_FORMAT,
              &err, "stdin:9: column 'x' expects a number, got '1e400', which is too large");
  CHECK_FAILS(core_csv_columns_read(&t, "stdin", 9, COLS, index, 3, v, &err), NBRDF_ERR_FORMAT,
              &err, "got '0.0001'");
  core_csv_free(&t);
}

int main(void) {
  RUN(test_find);
  RUN(test_read);
  return testing_finish();
}
