/* Input bounds: core/input_file.h refuses special files and oversized ones
 * before anything is allocated; core/csv.h refuses a line over 64 KiB,
 * naming it, while reading (so `< /dev/zero` stops there). */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/csv.h"
#include "core/input_file.h"
#include "testing.h"

static void test_special_files(void) {
  char dir[1024], fifo[1024], file[1024], link[1024];
  const char *tmp = testing_tmpdir();
  snprintf(dir, sizeof dir, "%s/in_dir", tmp);
  snprintf(fifo, sizeof fifo, "%s/in_fifo", tmp);
  snprintf(file, sizeof file, "%s/in_file", tmp);
  snprintf(link, sizeof link, "%s/in_link", tmp);
  CHECK(mkdir(dir, 0755) == 0);
  CHECK(mkfifo(fifo, 0644) == 0);
  CHECK(symlink("/dev/zero", link) == 0);
  FILE *f = fopen(file, "wb");
  if (f) fputs("0123456789", f), fclose(f);
  nbrdf_error err = {0};
  int fd = -1;
  uint64_t size = 0;
  CHECK_FAILS(core_input_open(dir, 100, &fd, &size, &err), NBRDF_ERR_IO, &err, "is a directory");
  CHECK(fd == -1);
  /* Must not block waiting for a writer. */
  CHECK_FAILS(core_input_open(fifo, 100, &fd, &size, &err), NBRDF_ERR_IO, &err,
              "in_fifo: is a FIFO");
  CHECK_FAILS(core_input_open(link, 100, &fd, &size, &err), NBRDF_ERR_IO, &err,
              "in_link: is a character device");
  CHECK_FAILS(core_input_check("/dev/zero", 100, &size, &err), NBRDF_ERR_IO, &err,
              "/dev/zero: is a character device");
  CHECK_FAILS(core_input_open(file, 9, &fd, &size, &err), NBRDF_ERR_FORMAT, &err,
              "in_file: 10 bytes, more than the 9");
  CHECK_OK(core_input_open(file, 10, &fd, &size, &err), &err);
  CHECK(fd >= 0 && size == 10);
  char buf[16];
  CHECK(fd >= 0 && read(fd, buf, sizeof buf) == 10); /* blocking mode restored, reads */
  if (fd >= 0) close(fd);
  CHECK_OK(core_input_check(file, NBRDF_INPUT_ANY_SIZE, &size, &err), &err);
  rmdir(dir), unlink(fifo), unlink(file), unlink(link);
}

static nbrdf_status parse_copy(const char *text, size_t len, core_csv_table *t, nbrdf_error *err) {
  char *copy = malloc(len ? len : 1);
  memcpy(copy, text, len);
  return core_csv_parse(copy, len, "in.csv", t, err);
}

static void test_csv_line_bound(void) {
  size_t n = CORE_CSV_LINE_MAX + 8;
  char *text = malloc(2 * n + 16);
  /* "a\n" then a line of exactly CORE_CSV_LINE_MAX bytes (CRLF): accepted */
  strcpy(text, "a\n");
  memset(text + 2, 'x', CORE_CSV_LINE_MAX);
  memcpy(text + 2 + CORE_CSV_LINE_MAX, "\r\n", 2);
  size_t len = 4 + CORE_CSV_LINE_MAX;
  core_csv_table t;
  nbrdf_error err = {0};
  CHECK_OK(parse_copy(text, len, &t, &err), &err);
  CHECK(t.n_records == 2);
  core_csv_free(&t);
  FILE *f = fmemopen(text, len, "rb");
  CHECK_OK(core_csv_read(f, "stdin", &t, &err), &err);
  fclose(f);
  core_csv_free(&t);
  /* one byte more on line 2: refused, naming line 2, in memory and streamed */
  text[2 + CORE_CSV_LINE_MAX] = 'x';
  memcpy(text + 3 + CORE_CSV_LINE_MAX, "\nb\n", 3);
  len = 6 + CORE_CSV_LINE_MAX;
  CHECK_FAILS(parse_copy(text, len, &t, &err), NBRDF_ERR_FORMAT, &err,
              "in.csv: line 2 is longer than 65536 bytes");
  f = fmemopen(text, len, "rb");
  CHECK_FAILS(core_csv_read(f, "stdin", &t, &err), NBRDF_ERR_FORMAT, &err,
              "stdin: line 2 is longer than 65536 bytes");
  fclose(f);
  free(text);
  /* An endless stream without line breaks stops at the bound. */
  f = fopen("/dev/zero", "rb");
  CHECK(f != NULL);
  if (f) {
    CHECK_FAILS(core_csv_read(f, "stdin", &t, &err), NBRDF_ERR_FORMAT, &err,
                "stdin: line 1 is longer");
    fclose(f);
  }
}

int main(void) {
  RUN(test_special_files);
  RUN(test_csv_line_bound);
  return testing_finish();
}
