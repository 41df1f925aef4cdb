/* The atomic-output module every writer uses (src/core/output_file.h). */
#include <dirent.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#include "core/output_file.h"
#include "testing.h"

static void fresh_dir(char *dir, size_t cap, const char *name) {
  snprintf(dir, cap, "%s/%s", testing_tmpdir(), name);
  mkdir(dir, 0777);
}

static int count_entries(const char *dir) {
  DIR *d = opendir(dir);
  if (!d) return -1;
  int n = 0;
  struct dirent *e;
  while ((e = readdir(d)) != NULL)
    n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
  closedir(d);
  return n;
}

static mode_t mode_of(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0 ? sb.st_mode : 0;
}

static void test_unnamed_temporary(void) {
  nbrdf_error e, *err = &e;
  char dir[512], path[600];
  fresh_dir(dir, sizeof dir, "unnamed");
  snprintf(path, sizeof path, "%s/out.bin", dir);
  core_output_file f;
  CHECK_OK(core_output_file_open(&f, path, NULL, 0, err), err);
  if (f.temp_path) {
    fprintf(stderr, "note: %s has no O_TMPFILE; the named fallback was used\n", dir);
    core_output_file_abort(&f);
    return;
  }
  CHECK(strncmp(core_output_file_name(&f), "/proc/self/fd/", 14) == 0);
  CHECK_OK(core_output_file_pwrite(&f, "hello", 5, 0, err), err);
  CHECK(count_entries(dir) == 0); /* nothing a SIGKILL could leave */
  CHECK_OK(core_output_file_commit(&f, err), err);
  CHECK(testing_file_is(path, "hello"));
  CHECK(count_entries(dir) == 1);
  mode_t mask = umask(0);
  umask(mask);
  CHECK((mode_of(path) & 07777) == (0666 & ~mask)); /* as any new file */

  /* Over an existing file: replaced whole, no other entry left. */
  CHECK_OK(core_output_file_open(&f, path, NULL, 0, err), err);
  CHECK_OK(core_output_file_pwrite(&f, "again", 5, 0, err), err);
  CHECK(testing_file_is(path, "hello"));
  CHECK_OK(core_output_file_commit(&f, err), err);
  CHECK(testing_file_is(path, "again"));
  CHECK(count_entries(dir) == 1);

  /* Abort: the old file stays, nothing else appears. */
  CHECK_OK(core_output_file_open(&f, path, NULL, 0, err), err);
  CHECK_OK(core_output_file_pwrite(&f, "lost", 4, 0, err), err);
  core_output_file_abort(&f);
  CHECK(testing_file_is(path, "again"));
  CHECK(count_entries(dir) == 1);

  /* A writer that opens the file by name (as OpenImageIO does) reaches the same file. */
  CHECK_OK(core_output_file_open(&f, path, NULL, 0, err), err);
  FILE *byname = fopen(core_output_file_name(&f), "wb");
  CHECK(byname != NULL);
  if (byname) {
    fputs("by name", byname);
    fclose(byname);
  }
  CHECK_OK(core_output_file_commit(&f, err), err);
  CHECK(testing_file_is(path, "by name"));
}

static void test_named_fallback(void) {
  nbrdf_error e, *err = &e;
  char dir[512], path[600];
  fresh_dir(dir, sizeof dir, "named");
  snprintf(path, sizeof path, "%s/out.bin", dir);
  core_output_file f;
  CHECK_OK(core_output_file_open_flags(&f, path, NULL, 0, NBRDF_OUTPUT_NAMED_TEMP, err), err);
  CHECK(f.temp_path != NULL);
  if (!f.temp_path) return;
  char expect[700];
  snprintf(expect, sizeof expect, "%s/.out.bin.", dir);
  CHECK(strncmp(f.temp_path, expect, strlen(expect)) == 0);
  CHECK(strcmp(f.temp_path + strlen(f.temp_path) - 4, ".tmp") == 0);
  CHECK(strlen(f.temp_path) == strlen(expect) + 8 + 4);
  CHECK(strcmp(core_output_file_name(&f), f.temp_path) == 0);
  CHECK_OK(core_output_file_pwrite(&f, "named", 5, 0, err), err);
  CHECK(count_entries(dir) == 1);
  CHECK_OK(core_output_file_commit(&f, err), err);
  CHECK(testing_file_is(path, "named"));
  CHECK(count_entries(dir) == 1);

  CHECK_OK(core_output_file_open_flags(&f, path, NULL, 0, NBRDF_OUTPUT_NAMED_TEMP, err), err);
  CHECK(count_entries(dir) == 2);
  core_output_file_abort(&f);
  CHECK(count_entries(dir) == 1);
  CHECK(testing_file_is(path, "named"));
}

/* What a killed writer leaves is removed by the next output into the directory; a live
 * writer's file (locked), a recent one and other names are kept. */
static void test_stale_temporaries_removed(void) {
  nbrdf_error e, *err = &e;
  char dir[512], stale[600], live[600], recent[600], other[600], path[600];
  fresh_dir(dir, sizeof dir, "stale");
  snprintf(stale, sizeof stale, "%s/.tex.exr.0123abcd.tmp", dir);
  snprintf(live, sizeof live, "%s/.tex.exr.89abcdef.tmp", dir);
  snprintf(recent, sizeof recent, "%s/.b.exr.00000000.tmp", dir);
  snprintf(other, sizeof other, "%s/.notes.0123abcd.tmp.txt", dir);
  testing_write_text(stale, "x"), testing_write_text(live, "x"), testing_write_text(recent, "x"),
      testing_write_text(other, "x");
  struct timeval old[2] = {{time(NULL) - 86400, 0}, {time(NULL) - 86400, 0}};
  CHECK(utimes(stale, old) == 0 && utimes(live, old) == 0 && utimes(other, old) == 0);
  int held = open(live, O_RDONLY);
  CHECK(held >= 0 && flock(held, LOCK_EX) == 0);
  snprintf(path, sizeof path, "%s/new.exr", dir);
  core_output_file f;
  CHECK_OK(core_output_file_open_flags(&f, path, NULL, 0, NBRDF_OUTPUT_NAMED_TEMP, err), err);
  CHECK(access(stale, F_OK) != 0);
  CHECK(access(live, F_OK) == 0);
  CHECK(access(recent, F_OK) == 0);
  CHECK(access(other, F_OK) == 0);
  core_output_file_abort(&f);
  close(held);
}

static void test_special_files_refused(void) {
  nbrdf_error e, *err = &e;
  char dir[512], fifo[600], link[600];
  fresh_dir(dir, sizeof dir, "special");
  snprintf(fifo, sizeof fifo, "%s/fifo", dir);
  CHECK(mkfifo(fifo, 0666) == 0);
  core_output_file f;
  CHECK_FAILS(core_output_file_open(&f, fifo, NULL, 0, err), NBRDF_ERR_ARGUMENT, err,
              "not a regular file");
  CHECK(strstr(err->message, fifo) == err->message);
  CHECK(S_ISFIFO(mode_of(fifo)));
  /* A symlink to /dev/null: refused; were it not, the rename would replace the link, never
   * /dev/null itself, so this is safe to run as root. */
  snprintf(link, sizeof link, "%s/null", dir);
  CHECK(symlink("/dev/null", link) == 0);
  CHECK_FAILS(core_output_file_open(&f, link, NULL, 0, err), NBRDF_ERR_ARGUMENT, err,
              "not a regular file");
  struct stat sb;
  CHECK(lstat(link, &sb) == 0 && S_ISLNK(sb.st_mode));
  CHECK(S_ISCHR(mode_of("/dev/null")));
  CHECK_FAILS(core_output_file_open(&f, dir, NULL, 0, err), NBRDF_ERR_ARGUMENT, err,
              "is a directory");
  CHECK(count_entries(dir) == 2);
}

/* The destination turns into a FIFO while the output is written: the commit refuses. */
static void test_commit_rechecks(void) {
  nbrdf_error e, *err = &e;
  char dir[512], path[600];
  fresh_dir(dir, sizeof dir, "recheck");
  snprintf(path, sizeof path, "%s/out", dir);
  core_output_file f;
  CHECK_OK(core_output_file_open(&f, path, NULL, 0, err), err);
  CHECK_OK(core_output_file_pwrite(&f, "data", 4, 0, err), err);
  CHECK(mkfifo(path, 0666) == 0);
  CHECK_FAILS(core_output_file_commit(&f, err), NBRDF_ERR_ARGUMENT, err, "not a regular file");
  CHECK(S_ISFIFO(mode_of(path)));
  CHECK(count_entries(dir) == 1);
}

/* Checked by the mode bits, not access(): the tests run as root in CI. */
static void test_read_only_refused_and_mode_kept(void) {
  nbrdf_error e, *err = &e;
  char dir[512], ro[600], rw[600];
  fresh_dir(dir, sizeof dir, "modes");
  snprintf(ro, sizeof ro, "%s/ro", dir);
  testing_write_text(ro, "keep");
  CHECK(chmod(ro, 0444) == 0);
  core_output_file f;
  CHECK_FAILS(core_output_file_open(&f, ro, NULL, 0, err), NBRDF_ERR_ARGUMENT, err, "read-only");
  CHECK(testing_file_is(ro, "keep"));
  CHECK((mode_of(ro) & 07777) == 0444);

  snprintf(rw, sizeof rw, "%s/rw", dir);
  testing_write_text(rw, "old");
  CHECK(chmod(rw, 0640) == 0);
  CHECK_OK(core_output_file_write_all(rw, "new", 3, NULL, 0, err), err);
  CHECK(testing_file_is(rw, "new"));
  CHECK((mode_of(rw) & 07777) == 0640);
  CHECK(chmod(rw, 0604) == 0);
  core_output_file g;
  CHECK_OK(core_output_file_open_flags(&g, rw, NULL, 0, NBRDF_OUTPUT_NAMED_TEMP, err), err);
  CHECK_OK(core_output_file_pwrite(&g, "named", 5, 0, err), err);
  CHECK_OK(core_output_file_commit(&g, err), err);
  CHECK((mode_of(rw) & 07777) == 0604);
  CHECK(count_entries(dir) == 2);
}

static void test_inputs_refused(void) {
  nbrdf_error e, *err = &e;
  char dir[512], input[600], sym[600], hard[600], dotdot[700];
  fresh_dir(dir, sizeof dir, "inputs");
  snprintf(input, sizeof input, "%s/map.png", dir);
  testing_write_text(input, "pixels");
  snprintf(sym, sizeof sym, "%s/sym.png", dir);
  snprintf(hard, sizeof hard, "%s/hard.png", dir);
  CHECK(symlink("map.png", sym) == 0);
  CHECK(link(input, hard) == 0);
  snprintf(dotdot, sizeof dotdot, "%s/../inputs/map.png", dir);
  const char *inputs[3] = {NULL, "/no/such/file", input};
  const char *outs[4] = {input, sym, hard, dotdot};
  for (int i = 0; i < 4; i++) {
    core_output_file f;
    CHECK_FAILS(core_output_file_open(&f, outs[i], inputs, 3, err), NBRDF_ERR_ARGUMENT, err,
                "refusing to overwrite an input");
    CHECK(strstr(err->message, outs[i]) == err->message);
    CHECK(strstr(err->message, input) != NULL);
    CHECK_FAILS(core_output_check(outs[i], inputs, 3, err), NBRDF_ERR_ARGUMENT, err,
                "is the input");
  }
  /* The input named through a link is caught the other way round too. */
  const char *via_link[1] = {sym};
  CHECK_FAILS(core_output_check(input, via_link, 1, err), NBRDF_ERR_ARGUMENT, err, "is the input");
  CHECK(testing_file_is(input, "pixels"));
  CHECK(count_entries(dir) == 3);
  char fresh[700];
  snprintf(fresh, sizeof fresh, "%s/new.png", dir);
  CHECK_OK(core_output_check(fresh, inputs, 3, err), err);
}

int main(void) {
  RUN(test_unnamed_temporary);
  RUN(test_named_fallback);
  RUN(test_stale_temporaries_removed);
  RUN(test_special_files_refused);
  RUN(test_commit_rechecks);
  RUN(test_read_only_refused_and_mode_kept);
  RUN(test_inputs_refused);
  return testing_finish();
}
