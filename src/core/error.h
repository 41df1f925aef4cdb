/* Internal helpers to fill an nbrdf_error. All accept err == NULL. */
#ifndef NBRDF_CORE_ERROR_H
#define NBRDF_CORE_ERROR_H

#include "nbrdf/status.h"

#if defined(__GNUC__)
#define NBRDF_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define NBRDF_PRINTF(f, a)
#endif

/* Records a failure and returns `status`, so callers can write
 * `return core_fail(err, NBRDF_ERR_ARGUMENT, "alpha is %g", a);`
 * A message longer than the buffer (NBRDF_ERROR_MESSAGE_MAX - 1 bytes) keeps
 * its reason: the middles of its longest words (paths of up to PATH_MAX
 * bytes) give way to an ellipsis, "ln/0000/…/nodir/x.exr: cannot create ...". */
nbrdf_status core_fail(nbrdf_error *err, nbrdf_status status, const char *fmt, ...)
    NBRDF_PRINTF(3, 4);

/* Puts context in front of an existing message ("r0.png: " + message),
 * shortened the same way. */
void core_error_prefix(nbrdf_error *err, const char *fmt, ...) NBRDF_PRINTF(2, 3);

void core_error_clear(nbrdf_error *err);

/* Checks that `value` is finite and within [lo, hi]; the message names the
 * parameter and the range. */
nbrdf_status core_check_range(nbrdf_error *err, const char *name, double value, double lo,
                              double hi);

#endif
