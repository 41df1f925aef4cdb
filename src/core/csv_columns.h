/* The numeric columns of a CSV table (core/csv.h) that a command reads: found by name in the
 * header, then read row by row with range checks. One reader and one message style for every
 * CSV input (`nbrdf eval`, `nbrdf eval --texture`):
 *   NAME:LINE: column 'theta_i' expects a number in [0, 90), got '95'
 * NAME is the input's name ("stdin", a path), LINE the physical line (core/csv.h). */
#ifndef NBRDF_CORE_CSV_COLUMNS_H
#define NBRDF_CORE_CSV_COLUMNS_H

#include <stddef.h>

#include "core/csv.h"
#include "nbrdf/status.h"

typedef struct core_csv_column {
  const char *name;
  double lo, hi; /* the accepted range; -INFINITY, INFINITY: any finite number */
  int hi_open;   /* hi itself is refused (theta = 90 degrees lies in the surface) */
} core_csv_column;

/* Finds each of the n columns cols[c] in the header (record 0) into index[c]. Refused, with
 * NBRDF_ERR_FORMAT: a header holding one of them twice, or a name of `reserved` (the columns
 * the output adds; NULL-terminated, may be NULL), or lacking one of them: "missing column
 * 'eta' (NEEDS)", `needs` saying what the input must hold. */
nbrdf_status core_csv_columns_find(const core_csv_table *t, const char *name,
                                   const core_csv_column *const *cols, int n,
                                   const char *const *reserved, const char *needs, size_t *index,
                                   nbrdf_error *err);

/* Reads the n columns of record r (>= 1) into v[c]: each a decimal number (core/number.h) in
 * its range, the record as wide as the header. NBRDF_ERR_FORMAT otherwise, naming the line,
 * the column, its range and the field as written. */
nbrdf_status core_csv_columns_read(const core_csv_table *t, const char *name, size_t r,
                                   const core_csv_column *const *cols, const size_t *index, int n,
                                   double *v, nbrdf_error *err);

#endif
