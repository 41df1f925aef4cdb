/* A minimal test harness: each tests/<layer>/test_*.c has a main() that calls
 * RUN(fn) for each test function and returns testing_finish().
 * Bytes, or values tighter than 1e-6 relative, may be compared only where the BLAS gets
 * identical inputs in identical shapes (same machine, batch composition, BLAS thread count)
 * or no network is involved; otherwise within float rounding, the bound and its reason in a
 * comment (tests/README.md). */
#ifndef NBRDF_TESTING_H
#define NBRDF_TESTING_H

#include <math.h>
#include <stddef.h>
#include <stdio.h>

#include "nbrdf/status.h"

extern int testing_failures;
extern int testing_checks;

void testing_fail(const char *file, int line, const char *fmt, ...);
int testing_finish(void);
/* A scratch directory unique to this test process, created on first use. */
const char *testing_tmpdir(void);
/* `name` inside testing_tmpdir(); the last four results stay valid. */
const char *testing_path(const char *name);
/* Re-executes the test once with OPENBLAS_NUM_THREADS=1 unless it is set so: tests
 * of fits run thousands of small GEMM steps, and OpenBLAS's 2-thread pool crawls on a
 * loaded machine (docs/ARCHITECTURE.md, "Threads under load"). Call first in main(). */
void testing_one_blas_thread(int argc, char **argv);
/* The message of an error, or "(no message)" for NULL. A function rather than
 * `(errp) ? ...` in the macros, which GCC rejects (-Waddress) for `&err`. */
const char *testing_message(const nbrdf_error *err);
/* Reads an 8-bit RGB PNG's size from its IHDR chunk; 0 if the file is not one. */
int testing_png_size(const char *path, int *w, int *h);
/* $NBRDF_SOURCE_DIR (the repository root), for fixtures. */
const char *testing_source_dir(void);
/* The names in `dir` not starting with '.', sorted (strdup'd, in a malloc'd
 * array: free each and the array); NULL, a failed CHECK, when it cannot be read. */
char **testing_list_dir(const char *dir, size_t *n);
/* Writes `text` to `path` (nothing on failure: the test's next CHECK sees it). */
void testing_write_text(const char *path, const char *text);
/* 1 when the file at `path` holds exactly `text` (up to 255 bytes). */
int testing_file_is(const char *path, const char *text);

#define RUN(fn)                                                                                    \
  do {                                                                                             \
    int before_ = testing_failures;                                                                \
    fn();                                                                                          \
    printf("%s %s\n", testing_failures == before_ ? "ok  " : "FAIL", #fn);                         \
    fflush(stdout);                                                                                \
  } while (0)

#define CHECK(cond)                                                                                \
  do {                                                                                             \
    testing_checks++;                                                                              \
    if (!(cond)) testing_fail(__FILE__, __LINE__, "CHECK(%s)", #cond);                             \
  } while (0)

#define CHECK_MSG(cond, ...)                                                                       \
  do {                                                                                             \
    testing_checks++;                                                                              \
    if (!(cond)) testing_fail(__FILE__, __LINE__, __VA_ARGS__);                                    \
  } while (0)

/* |a - b| <= tol, and neither is NaN. */
#define CHECK_NEAR(a, b, tol)                                                                      \
  do {                                                                                             \
    double a_ = (double)(a), b_ = (double)(b), t_ = (double)(tol);                                 \
    testing_checks++;                                                                              \
    if (!(fabs(a_ - b_) <= t_))                                                                    \
      testing_fail(__FILE__, __LINE__, "CHECK_NEAR(%s, %s): %.9g vs %.9g, tol %.3g", #a, #b, a_,   \
                   b_, t_);                                                                        \
  } while (0)

/* |a - b| <= rel * max(|a|, |b|) + abs_tol. */
#define CHECK_REL(a, b, rel, abs_tol)                                                              \
  do {                                                                                             \
    double a_ = (double)(a), b_ = (double)(b);                                                     \
    double t_ = (double)(rel)*fmax(fabs(a_), fabs(b_)) + (double)(abs_tol);                        \
    testing_checks++;                                                                              \
    if (!(fabs(a_ - b_) <= t_))                                                                    \
      testing_fail(__FILE__, __LINE__, "CHECK_REL(%s, %s): %.9g vs %.9g (rel %.3g)", #a, #b, a_,   \
                   b_, (double)(rel));                                                             \
  } while (0)

/* A call returning nbrdf_status must succeed; prints the error message if not. */
#define CHECK_OK(call, errp)                                                                       \
  do {                                                                                             \
    testing_checks++;                                                                              \
    nbrdf_status s_ = (call);                                                                      \
    if (s_ != NBRDF_OK)                                                                            \
      testing_fail(__FILE__, __LINE__, "%s failed: %s", #call, testing_message(errp));             \
  } while (0)

/* A call must fail with `status` and a message containing `needle`. */
#define CHECK_FAILS(call, status, errp, needle)                                                    \
  do {                                                                                             \
    testing_checks++;                                                                              \
    nbrdf_status s_ = (call);                                                                      \
    if (s_ != (status))                                                                            \
      testing_fail(__FILE__, __LINE__, "%s returned %s, expected %s", #call,                       \
                   nbrdf_status_name(s_), nbrdf_status_name(status));                              \
    else if (!strstr((errp)->message, (needle)))                                                   \
      testing_fail(__FILE__, __LINE__, "%s: message \"%s\" lacks \"%s\"", #call, (errp)->message,  \
                   (needle));                                                                      \
  } while (0)

#endif
