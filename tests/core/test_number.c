/* core/number.h: the one parser of typed numbers. */
#include <string.h>

#include "core/number.h"
#include "testing.h"

static core_number_result parse(const char *s, double *v) {
  return core_parse_number(s, strlen(s), v);
}

static void test_accepted(void) {
  static const struct {
    const char *text;
    double value;
  } ok[] = {{"0.1", 0.1},   {"0.1 ", 0.1}, {" \t0.1\n", 0.1}, {"-2", -2},        {"+.5", 0.5},
            {"5.", 5},      {"1e3", 1000}, {"1E-3", 1e-3},    {"0e999", 0},      {"0.000", 0},
            {"-0", 0},      {"1e308", 1e308}};
  for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
    double v = -1;
    CHECK_MSG(parse(ok[i].text, &v) == NBRDF_NUMBER_OK, "'%s' refused", ok[i].text);
    CHECK_MSG(v == ok[i].value, "'%s' read as %g", ok[i].text, v);
  }
}

static void test_refused(void) {
  static const char *const syntax[] = {"",    " ",     "0x10", "0X1p3", "inf", "-inf", "nan",
                                        "NAN", "1e",    "1e+",  ".",     "+",   "1..2", "1,2",
                                        "1 2", "0.1a",  "e5",   "--1",   "1e5x"};
  for (size_t i = 0; i < sizeof syntax / sizeof syntax[0]; i++) {
    double v = 42;
    CHECK_MSG(parse(syntax[i], &v) == NBRDF_NUMBER_SYNTAX, "'%s' accepted", syntax[i]);
    CHECK(v == 42);
  }
  double v;
  CHECK(parse("1e400", &v) == NBRDF_NUMBER_OVERFLOW);
  CHECK(parse("-1e400", &v) == NBRDF_NUMBER_OVERFLOW);
  CHECK(parse("1e-400", &v) == NBRDF_NUMBER_UNDERFLOW);
  CHECK(parse("1e-320", &v) == NBRDF_NUMBER_UNDERFLOW); /* subnormal */
  /* len bounds the text: "0.5" of "0.5,0.7" */
  CHECK(core_parse_number("0.5,0.7", 3, &v) == NBRDF_NUMBER_OK && v == 0.5);
  float f;
  CHECK(core_parse_float("1e39", 4, &f) == NBRDF_NUMBER_OVERFLOW);
  CHECK(core_parse_float("1e-39", 5, &f) == NBRDF_NUMBER_UNDERFLOW);
  CHECK(core_parse_float("0.25 ", 5, &f) == NBRDF_NUMBER_OK && f == 0.25f);
  CHECK(strstr(core_number_problem(NBRDF_NUMBER_UNDERFLOW), "underflow") != NULL);
}

int main(void) {
  RUN(test_accepted);
  RUN(test_refused);
  return testing_finish();
}
