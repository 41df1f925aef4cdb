#include "core/input_file.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"

static const char *kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

static nbrdf_status check_stat(const char *path, const struct stat *sb, uint64_t max_bytes,
                               uint64_t *size, nbrdf_error *err) {
  if (!S_ISREG(sb->st_mode))
    return core_fail(err, NBRDF_ERR_IO, "%s: is %s, not a file", path, kind_of(sb->st_mode));
  uint64_t n = sb->st_size > 0 ? (uint64_t)sb->st_size : 0;
  if (n > max_bytes)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: %llu bytes, more than the %llu a file of this kind may have", path,
                     (unsigned long long)n, (unsigned long long)max_bytes);
  if (size) *size = n;
  return NBRDF_OK;
}

nbrdf_status core_input_check(const char *path, uint64_t max_bytes, uint64_t *size,
                              nbrdf_error *err) {
  if (!path) return core_fail(err, NBRDF_ERR_ARGUMENT, "input path is NULL");
  struct stat sb;
  if (stat(path, &sb) != 0)
    return core_fail(err, NBRDF_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  return check_stat(path, &sb, max_bytes, size, err);
}

nbrdf_status core_input_open_stream(const char *path, int *fd, nbrdf_error *err) {
  *fd = -1;
  if (!path) return core_fail(err, NBRDF_ERR_ARGUMENT, "input path is NULL");
  struct stat sb;
  if (stat(path, &sb) != 0)
    return core_fail(err, NBRDF_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  if (!S_ISFIFO(sb.st_mode)) return core_input_open(path, NBRDF_INPUT_ANY_SIZE, fd, NULL, err);
  /* Blocking: a non-blocking open of a FIFO without a writer yet would read as empty. */
  int f = open(path, O_RDONLY | O_CLOEXEC | O_NOCTTY);
  if (f < 0) return core_fail(err, NBRDF_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  /* What was opened, not what stat saw: the name may have been replaced meanwhile. */
  if (fstat(f, &sb) != 0 || !S_ISFIFO(sb.st_mode)) {
    close(f);
    return core_input_open(path, NBRDF_INPUT_ANY_SIZE, fd, NULL, err);
  }
  *fd = f;
  return NBRDF_OK;
}

nbrdf_status core_input_open(const char *path, uint64_t max_bytes, int *fd, uint64_t *size,
                             nbrdf_error *err) {
  if (fd) *fd = -1;
  if (!path) return core_fail(err, NBRDF_ERR_ARGUMENT, "input path is NULL");
  /* O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer. */
  int f = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (f < 0) return core_fail(err, NBRDF_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  struct stat sb;
  nbrdf_status st = NBRDF_OK;
  if (fstat(f, &sb) != 0)
    st = core_fail(err, NBRDF_ERR_IO, "%s: cannot stat: %s", path, strerror(errno));
  if (st == NBRDF_OK) st = check_stat(path, &sb, max_bytes, size, err);
  if (st == NBRDF_OK) {
    int flags = fcntl(f, F_GETFL);
    if (flags < 0 || fcntl(f, F_SETFL, flags & ~O_NONBLOCK) != 0)
      st = core_fail(err, NBRDF_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  }
  if (st != NBRDF_OK || !fd) {
    close(f);
    return st;
  }
  *fd = f;
  return NBRDF_OK;
}
