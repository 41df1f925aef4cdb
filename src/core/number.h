/* The one parser of numbers typed by people: command-line values, CSV
 * fields, parameter lists. Accepted: optional surrounding white space, then
 * [+-] digits [. digits] [(e|E) [+-] digits] (at least one digit before the
 * exponent). Refused: hexadecimal ("0x10", which strtod reads as 16),
 * "inf", "nan", and trailing text. A value that overflows or underflows a
 * double (1e400, 1e-400) is told apart from "not a number", so that a
 * caller can say so rather than take the text for a file name. */
#ifndef NBRDF_CORE_NUMBER_H
#define NBRDF_CORE_NUMBER_H

#include <stddef.h>

typedef enum core_number_result {
  NBRDF_NUMBER_OK = 0,
  NBRDF_NUMBER_SYNTAX = 1,    /* not a decimal number */
  NBRDF_NUMBER_OVERFLOW = 2,  /* |value| beyond the largest double */
  NBRDF_NUMBER_UNDERFLOW = 3, /* a non-zero value that rounds to 0 or a subnormal */
} core_number_result;

/* Parses text[0..len) entirely (len: strlen for a string). Sets *out only on
 * NBRDF_NUMBER_OK. */
core_number_result core_parse_number(const char *text, size_t len, double *out);

/* The same for a float (overflow and underflow judged against float). */
core_number_result core_parse_float(const char *text, size_t len, float *out);

/* "is not a number", "overflows", "underflows": for messages. */
const char *core_number_problem(core_number_result r);

#endif
