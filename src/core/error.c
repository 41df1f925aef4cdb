#include "core/error.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
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

/* U+2026 HORIZONTAL ELLIPSIS in UTF-8: marks where a long word lost its middle. */
static const char kEllipsis[] = "\xe2\x80\xa6";
enum { ELLIPSIS_LEN = 3, WORD_KEEP = 24 };

static int is_space(char c) { return c == ' ' || c == '\n' || c == '\t'; }
static int is_continuation(char c) { return ((unsigned char)c & 0xC0) == 0x80; }

static int has_ellipsis(const char *word, size_t n) {
  for (size_t i = 0; i + ELLIPSIS_LEN <= n; i++)
    if (!memcmp(word + i, kEllipsis, ELLIPSIS_LEN)) return 1;
  return 0;
}

/* Cuts text[from, to) out of the string of *len bytes and puts the ellipsis there. */
static void elide(char *text, size_t *len, size_t from, size_t to) {
  memmove(text + from + ELLIPSIS_LEN, text + to, *len - to + 1);
  memcpy(text + from, kEllipsis, ELLIPSIS_LEN);
  *len = *len - (to - from) + ELLIPSIS_LEN;
}

/* Shortens the word text[a, b) by at least `excess` bytes where it can, keeping its first
 * third and last two thirds (a path keeps its root and its file name), cut at '/' where one is
 * near. Returns 0 when the word is too short to gain anything. */
static int shorten_word(char *text, size_t *len, size_t a, size_t b, size_t excess) {
  size_t n = b - a;
  if (n <= WORD_KEEP) return 0;
  size_t keep = n > excess + ELLIPSIS_LEN + WORD_KEEP ? n - excess - ELLIPSIS_LEN : WORD_KEEP;
  size_t head_end = a + keep / 3, tail_start = b - (keep - keep / 3);
  /* Whole path components read better: end the head after a '/', start the tail at one. */
  for (size_t i = head_end; i > a + keep / 6; i--)
    if (text[i - 1] == '/') {
      head_end = i;
      break;
    }
  for (size_t i = tail_start; i < b - keep / 3; i++)
    if (text[i] == '/') {
      tail_start = i;
      break;
    }
  /* Never split a UTF-8 sequence. */
  while (head_end > a && is_continuation(text[head_end]))
    head_end--;
  while (tail_start < b && is_continuation(text[tail_start]))
    tail_start++;
  if (tail_start <= head_end + ELLIPSIS_LEN) return 0;
  elide(text, len, head_end, tail_start);
  return 1;
}

/* Copies text (len bytes, modified) into a message buffer of `cap` bytes. When it is longer,
 * the middles of its longest words (paths, in practice: a path may be PATH_MAX = 4096 bytes,
 * the buffer holds 512) are replaced by an ellipsis until it fits, so that what a message says
 * about the file (its reason, usually at the end) is never lost to a long name. */
static void fit(char *dst, size_t cap, char *text, size_t len) {
  for (int round = 0; round < 16 && len >= cap; round++) {
    size_t best_a = 0, best_n = 0;
    for (size_t i = 0; i < len;) {
      while (i < len && is_space(text[i]))
        i++;
      size_t a = i;
      while (i < len && !is_space(text[i]))
        i++;
      /* A word that already lost its middle is not cut again. */
      if (i - a > best_n && !has_ellipsis(text + a, i - a))
        best_a = a, best_n = i - a;
    }
    if (!shorten_word(text, &len, best_a, best_a + best_n, len - (cap - 1))) break;
  }
  if (len >= cap) {
    /* Many short words: keep the start and the (longer) end of the whole message. */
    size_t room = cap - 1 - ELLIPSIS_LEN, head = room / 3, tail = len - (room - head);
    while (head > 0 && is_continuation(text[head]))
      head--;
    while (tail < len && is_continuation(text[tail]))
      tail++;
    elide(text, &len, head, tail);
  }
  memcpy(dst, text, len + 1);
}

/* Formats into a scratch buffer (on the stack up to two PATH_MAX paths and their text), then
 * fits the result into `dst`. */
static void format_fitted(char *dst, size_t cap, const char *fmt, va_list ap) {
  char local[16384];
  char *text = local;
  size_t size = sizeof local;
  va_list again;
  va_copy(again, ap);
  int n = vsnprintf(NULL, 0, fmt, again);
  va_end(again);
  if (n >= 0 && (size_t)n + 1 > size) {
    char *big = malloc((size_t)n + 1);
    if (big) text = big, size = (size_t)n + 1;
  }
  vsnprintf(text, size, fmt, ap);
  fit(dst, cap, text, strlen(text));
  if (text != local) free(text);
}

nbrdf_status core_fail(nbrdf_error *err, nbrdf_status status, const char *fmt, ...) {
  if (err) {
    va_list ap;
    va_start(ap, fmt);
    format_fitted(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    err->status = status;
  }
  return status;
}

void core_error_prefix(nbrdf_error *err, const char *fmt, ...) {
  if (!err) return;
  /* The prefix (often a path) and the message are fitted together, so that a long prefix
   * shortens itself rather than pushing the message's reason out. */
  char old[sizeof err->message];
  memcpy(old, err->message, sizeof old);
  old[sizeof old - 1] = '\0';
  char *prefix = NULL;
  va_list ap, again;
  va_start(ap, fmt);
  va_copy(again, ap);
  int n = vsnprintf(NULL, 0, fmt, again);
  va_end(again);
  if (n >= 0 && (prefix = malloc((size_t)n + 1))) vsnprintf(prefix, (size_t)n + 1, fmt, ap);
  va_end(ap);
  core_fail(err, err->status, "%s%s", prefix ? prefix : "", old);
  free(prefix);
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
