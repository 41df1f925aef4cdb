#include "testing.h"

#include <dirent.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int testing_failures = 0;
int testing_checks = 0;
static char tmpdir_path[256];

void testing_fail(const char *file, int line, const char *fmt, ...) {
  testing_failures++;
  fprintf(stderr, "%s:%d: ", file, line);
  va_list ap;
  va_start(ap, fmt);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fputc('\n', stderr);
}

int testing_finish(void) {
  printf("%d checks, %d failed\n", testing_checks, testing_failures);
  if (tmpdir_path[0] && testing_failures == 0) {
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir_path);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir_path);
  }
  return testing_failures == 0 ? 0 : 1;
}

const char *testing_tmpdir(void) {
  if (!tmpdir_path[0]) {
    const char *base = getenv("TMPDIR");
    snprintf(tmpdir_path, sizeof tmpdir_path, "%s/nbrdf-test-XXXXXX", base ? base : "/tmp");
    if (!mkdtemp(tmpdir_path)) {
      perror("mkdtemp");
      exit(2);
    }
  }
  return tmpdir_path;
}

const char *testing_path(const char *name) {
  static char buf[4][4096 + 256];
  static int k;
  k = (k + 1) % 4;
  snprintf(buf[k], sizeof buf[k], "%s/%s", testing_tmpdir(), name);
  return buf[k];
}

void testing_one_blas_thread(int argc, char **argv) {
  const char *bt = getenv("OPENBLAS_NUM_THREADS");
  if (argc >= 1 && (!bt || strcmp(bt, "1"))) {
    setenv("OPENBLAS_NUM_THREADS", "1", 1);
    execv("/proc/self/exe", argv);
  }
}

const char *testing_source_dir(void) {
  const char *s = getenv("NBRDF_SOURCE_DIR");
  return s ? s : ".";
}

const char *testing_message(const nbrdf_error *err) { return err ? err->message : "(no message)"; }

int testing_png_size(const char *path, int *w, int *h) {
  unsigned char b[26];
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  size_t got = fread(b, 1, sizeof b, f);
  fclose(f);
  if (got != sizeof b || memcmp(b, "\x89PNG\r\n\x1a\n", 8) || memcmp(b + 12, "IHDR", 4)) return 0;
  *w = (b[16] << 24) | (b[17] << 16) | (b[18] << 8) | b[19];
  *h = (b[20] << 24) | (b[21] << 16) | (b[22] << 8) | b[23];
  return b[24] == 8 && b[25] == 2;
}

static int compare_names(const void *a, const void *b) {
  return strcmp(*(char *const *)a, *(char *const *)b);
}

char **testing_list_dir(const char *dir, size_t *n) {
  *n = 0;
  DIR *d = opendir(dir);
  CHECK_MSG(d != NULL, "cannot open %s", dir);
  if (!d) return NULL;
  char **names = NULL;
  for (struct dirent *e; (e = readdir(d));) {
    if (e->d_name[0] == '.') continue;
    char **more = realloc(names, (*n + 1) * sizeof *names);
    if (!more) break;
    names = more;
    names[(*n)++] = strdup(e->d_name);
  }
  closedir(d);
  if (names) qsort(names, *n, sizeof *names, compare_names);
  return names ? names : calloc(1, sizeof *names);
}

void testing_write_text(const char *path, const char *text) {
  FILE *f = fopen(path, "wb");
  if (f) {
    fputs(text, f);
    fclose(f);
  }
}

int testing_file_is(const char *path, const char *text) {
  char buf[256] = {0};
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  fclose(f);
  return n == strlen(text) && memcmp(buf, text, n) == 0;
}
