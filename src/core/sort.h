/* Ascending sort of doubles: the medians and percentiles of evaluate, verify,
 * the bake's held-out check and the lobe metrics all start with it. NaNs
 * compare equal to everything (callers pass finite errors). */
#ifndef NBRDF_CORE_SORT_H
#define NBRDF_CORE_SORT_H

#include <stddef.h>

void core_sort_doubles(double *v, size_t n);

#endif
