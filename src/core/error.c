#include "core/error.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

const char *nbrdf_status_name(nbrdf_status status) {
  switch (status) {
  case NBRDF_OK: return "ok";
  case NBRDF_ERR_ARGUMENT: return "argument";
  case NBRDF_ERR_IO: return "io";
  case NBRDF_ERR_FORMAT: return "format";
  case NBRDF_ERR_MISMATCH: return "mismatch";
  case NBRDF_ERR_MEMORY: return "memory";
  case NBRDF_ERR_CANCELLED: return "cancelled";
  case NBRDF_ERR_UNSUPPORTED: return "unsupported";
  case NBRDF_ERR_INTERNAL: return "internal";
  }
  return "unknown";
}

nbrdf_status core_fail(nbrdf_error *err, nbrdf_status status, const char *fmt, ...) {
  if (err) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    err->status = status;
  }
  return status;
}

void core_error_prefix(nbrdf_error *err, const char *fmt, ...) {
  if (!err) return;
  char prefix[NBRDF_ERROR_MESSAGE_MAX];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(prefix, sizeof prefix, fmt, ap);
  va_end(ap);
  /* Truncation of an over-long message is acceptable; keep its end NUL-terminated. */
  size_t plen = strlen(prefix), mlen = strlen(err->message);
  if (plen >= sizeof err->message) plen = sizeof err->message - 1;
  if (plen + mlen >= sizeof err->message) mlen = sizeof err->message - 1 - plen;
  memmove(err->message + plen, err->message, mlen);
  memcpy(err->message, prefix, plen);
  err->message[plen + mlen] = '\0';
}

void core_error_clear(nbrdf_error *err) {
  if (!err) return;
  err->status = NBRDF_OK;
  err->message[0] = '\0';
}

nbrdf_status core_check_range(nbrdf_error *err, const char *name, double value, double lo,
                              double hi) {
  if (isnan(value)) return core_fail(err, NBRDF_ERR_ARGUMENT, "%s is NaN", name);
  if (isinf(value)) return core_fail(err, NBRDF_ERR_ARGUMENT, "%s is infinite", name);
  if (value < lo || value > hi)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s = %g is outside [%g, %g]", name, value, lo,
                      hi);
  return NBRDF_OK;
}
