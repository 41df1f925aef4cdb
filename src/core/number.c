#include "core/number.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}
static int is_digit(char c) { return c >= '0' && c <= '9'; }

core_number_result core_parse_number(const char *text, size_t len, double *out) {
  if (!text) return NBRDF_NUMBER_SYNTAX;
  const char *a = text, *b = text + len;
  while (a < b && is_space(*a))
    a++;
  while (b > a && is_space(b[-1]))
    b--;
  /* Validate the grammar first: strtod alone would take hex, inf and nan. */
  const char *p = a;
  int digits = 0, nonzero = 0;
  if (p < b && (*p == '+' || *p == '-')) p++;
  for (; p < b && is_digit(*p); p++)
    digits++, nonzero |= *p != '0';
  if (p < b && *p == '.')
    for (p++; p < b && is_digit(*p); p++)
      digits++, nonzero |= *p != '0';
  if (!digits) return NBRDF_NUMBER_SYNTAX;
  if (p < b && (*p == 'e' || *p == 'E')) {
    p++;
    if (p < b && (*p == '+' || *p == '-')) p++;
    if (p == b || !is_digit(*p)) return NBRDF_NUMBER_SYNTAX;
    while (p < b && is_digit(*p))
      p++;
  }
  if (p != b) return NBRDF_NUMBER_SYNTAX;
  /* strtod needs a terminated string; numbers people type are short. */
  char buf[512];
  size_t n = (size_t)(b - a);
  if (n >= sizeof buf) return NBRDF_NUMBER_SYNTAX;
  memcpy(buf, a, n);
  buf[n] = '\0';
  char *end;
  errno = 0;
  double v = strtod(buf, &end);
  if (end != buf + n) return NBRDF_NUMBER_SYNTAX;
  if (isinf(v)) return NBRDF_NUMBER_OVERFLOW;
  if (nonzero && (v == 0.0 || (errno == ERANGE && fabs(v) < DBL_MIN)))
    return NBRDF_NUMBER_UNDERFLOW;
  *out = v;
  return NBRDF_NUMBER_OK;
}

core_number_result core_parse_float(const char *text, size_t len, float *out) {
  double d;
  core_number_result r = core_parse_number(text, len, &d);
  if (r != NBRDF_NUMBER_OK) return r;
  if (fabs(d) > FLT_MAX) return NBRDF_NUMBER_OVERFLOW;
  if (d != 0.0 && fabs(d) < FLT_MIN) return NBRDF_NUMBER_UNDERFLOW;
  *out = (float)d;
  return NBRDF_NUMBER_OK;
}

const char *core_number_problem(core_number_result r) {
  switch (r) {
  case NBRDF_NUMBER_OK:
    break;
  case NBRDF_NUMBER_SYNTAX:
    return "is not a number";
  case NBRDF_NUMBER_OVERFLOW:
    return "is too large (overflows)";
  case NBRDF_NUMBER_UNDERFLOW:
    return "is too small to tell from 0 (underflows)";
  }
  return "is a number";
}
