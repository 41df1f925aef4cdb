/* Status codes and error messages shared by every nbrdf call.
 *
 * Every fallible call returns an nbrdf_status and takes an optional
 * `nbrdf_error *err` as its last argument; on failure the message says what
 * was wrong and where ("r0.png: texel (41, 7) is NaN"). Errors travel in a
 * caller-owned struct rather than inside handles because read-only handles
 * (a loaded model, a BRDF) are shared between threads. */
#ifndef NBRDF_STATUS_H
#define NBRDF_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum nbrdf_status {
  NBRDF_OK = 0,
  NBRDF_ERR_ARGUMENT,    /* a parameter is NaN, Inf, negative or outside its range */
  NBRDF_ERR_IO,          /* a file cannot be opened, read, written or renamed */
  NBRDF_ERR_FORMAT,      /* a file or stream is malformed, truncated or of another version */
  NBRDF_ERR_MISMATCH,    /* inputs disagree with each other (sizes, model checksum) */
  NBRDF_ERR_MEMORY,      /* an allocation failed */
  NBRDF_ERR_CANCELLED,   /* the caller's progress callback or cancel flag stopped the work */
  NBRDF_ERR_UNSUPPORTED, /* a valid request this build cannot serve */
  NBRDF_ERR_INTERNAL     /* a bug in nbrdf: please report it with the message */
} nbrdf_status;

/* A longer message (a path may be 4096 bytes) keeps its start, its end and its
 * reason: the middle of its longest paths is replaced by "…" (UTF-8). */
#define NBRDF_ERROR_MESSAGE_MAX 512

typedef struct nbrdf_error {
  nbrdf_status status;
  char message[NBRDF_ERROR_MESSAGE_MAX];
} nbrdf_error;

/* A short constant name for a status ("argument", "io", ...). */
const char *nbrdf_status_name(nbrdf_status status);

/* Progress report for long-running calls: `done` of `total` units of the named
 * stage. Return non-zero to cancel; the call then returns NBRDF_ERR_CANCELLED
 * and leaves no partial output behind. */
typedef int (*nbrdf_progress_fn)(void *user, const char *stage, double done, double total);

#ifdef __cplusplus
}
#endif
#endif
