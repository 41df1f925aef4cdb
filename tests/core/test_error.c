/* core/error.h: a message longer than nbrdf_error's buffer keeps its reason. */
#include <string.h>

#include "core/error.h"
#include "testing.h"

static const char kEllipsis[] = "\xe2\x80\xa6";

/* A path of n bytes: 250-byte components, then "/x.exr". */
static void long_path(char *p, size_t n) {
  size_t i = 0;
  memcpy(p, "ln/", 3), i = 3;
  while (i + 6 < n) {
    p[i] = (i % 251 == 0) ? '/' : 'a' + (char)(i % 26);
    i++;
  }
  memcpy(p + i, "/x.exr", 7);
}

static int ends_with(const char *s, const char *end) {
  size_t a = strlen(s), b = strlen(end);
  return a >= b && !strcmp(s + a - b, end);
}

static void test_short_message_unchanged(void) {
  nbrdf_error err = {0};
  CHECK(core_fail(&err, NBRDF_ERR_IO, "%s: cannot open: %s", "a.png", "No such file") ==
        NBRDF_ERR_IO);
  CHECK(!strcmp(err.message, "a.png: cannot open: No such file"));
  CHECK(err.status == NBRDF_ERR_IO);
  core_error_prefix(&err, "%s: ", "alpha1");
  CHECK(!strcmp(err.message, "alpha1: a.png: cannot open: No such file"));
}

static void test_long_path_keeps_reason(void) {
  static char path[4100];
  long_path(path, 4000);
  nbrdf_error err = {0};
  core_fail(&err, NBRDF_ERR_IO, "%s: cannot create a file in '%s': No such file or directory",
            path, path);
  size_t n = strlen(err.message);
  CHECK_MSG(n < sizeof err.message, "%zu bytes", n);
  CHECK_MSG(n > sizeof err.message / 2, "%zu bytes: shortened more than needed", n);
  CHECK_MSG(ends_with(err.message, "/x.exr': No such file or directory"), "%s", err.message);
  CHECK_MSG(!strncmp(err.message, "ln/", 3), "%s", err.message);
  CHECK_MSG(strstr(err.message, "/x.exr: cannot create a file in 'ln/"), "%s", err.message);
  CHECK_MSG(strstr(err.message, kEllipsis), "%s", err.message);
  /* A prefix that is itself a long path shortens itself, not the reason. */
  core_error_prefix(&err, "%s: ", path);
  CHECK_MSG(ends_with(err.message, "No such file or directory"), "%s", err.message);
  CHECK(strlen(err.message) < sizeof err.message);
}

static void test_many_short_words(void) {
  /* No long word to shorten: the start and the end of the message survive. */
  static char text[3000];
  for (size_t i = 0; i + 1 < sizeof text; i++)
    text[i] = i % 4 == 3 ? ' ' : 'w';
  text[sizeof text - 1] = '\0';
  nbrdf_error err = {0};
  core_fail(&err, NBRDF_ERR_FORMAT, "start %s the reason", text);
  CHECK(strlen(err.message) < sizeof err.message);
  CHECK_MSG(!strncmp(err.message, "start ", 6), "%s", err.message);
  CHECK_MSG(ends_with(err.message, " the reason"), "%s", err.message);
}

static void test_utf8_not_split(void) {
  /* A path of two-byte characters is cut between characters. */
  static char path[4000];
  size_t i = 0;
  for (; i + 2 < sizeof path; i += 2)
    memcpy(path + i, "\xc3\xa9", 2);
  path[i] = '\0';
  nbrdf_error err = {0};
  core_fail(&err, NBRDF_ERR_IO, "%s: is a directory", path);
  const unsigned char *m = (const unsigned char *)err.message;
  for (size_t k = 0; m[k]; k++)
    if ((m[k] & 0xC0) == 0x80)
      CHECK_MSG(k > 0 && (m[k - 1] & 0x80), "stray continuation byte at %zu", k);
  CHECK(ends_with(err.message, ": is a directory"));
}

int main(void) {
  test_short_message_unchanged();
  test_long_path_keeps_reason();
  test_many_short_words();
  test_utf8_not_split();
  return testing_finish();
}
