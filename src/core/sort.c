/* core_sort_doubles of sort.h. */
#include "core/sort.h"

#include <stdlib.h>

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

void core_sort_doubles(double *v, size_t n) { qsort(v, n, sizeof *v, cmp_double); }
