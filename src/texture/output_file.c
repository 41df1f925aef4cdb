#include "texture/output_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/error.h"

static void release(nbrdf_output_file *f) {
  free(f->path);
  free(f->temp_path);
  f->path = f->temp_path = NULL;
  f->fd = -1;
}

static nbrdf_status check_not_an_input(const char *path, const char *const *inputs, int n_inputs,
                                       nbrdf_error *err) {
  struct stat out;
  if (stat(path, &out) != 0) return NBRDF_OK; /* a new file cannot be an input */
  if (S_ISDIR(out.st_mode)) return nbrdf_fail(err, NBRDF_ERR_ARGUMENT, "%s: is a directory", path);
  for (int i = 0; i < n_inputs; i++) {
    struct stat in;
    if (!inputs[i] || stat(inputs[i], &in) != 0) continue;
    if (in.st_dev == out.st_dev && in.st_ino == out.st_ino)
      return nbrdf_fail(err, NBRDF_ERR_ARGUMENT,
                        "%s: the output is the input '%s'; refusing to overwrite an input", path,
                        inputs[i]);
  }
  return NBRDF_OK;
}

nbrdf_status nbrdf_output_file_open(nbrdf_output_file *f, const char *path,
                                    const char *const *inputs, int n_inputs, nbrdf_error *err) {
  f->path = f->temp_path = NULL;
  f->fd = -1;
  if (!path || !path[0]) return nbrdf_fail(err, NBRDF_ERR_ARGUMENT, "output path is empty");
  const char *slash = strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  if (!base[0] || strcmp(base, ".") == 0 || strcmp(base, "..") == 0)
    return nbrdf_fail(err, NBRDF_ERR_ARGUMENT, "%s: is a directory", path);
  nbrdf_status st = check_not_an_input(path, inputs, n_inputs, err);
  if (st != NBRDF_OK) return st;

  int dir_len = slash ? (int)(slash - path) : 1;
  const char *dir = slash ? path : ".";
  if (slash && dir_len == 0) dir_len = 1; /* "/name": the root directory */
  size_t cap = strlen(path) + 32;
  f->path = strdup(path);
  f->temp_path = malloc(cap);
  if (!f->path || !f->temp_path) {
    release(f);
    return nbrdf_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  }
  /* A fresh name per attempt; O_EXCL makes a clash harmless. The seed mixes
   * the clock, the process and this struct's address, so no shared counter
   * is needed between threads. */
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  uint64_t seed = (uint64_t)ts.tv_nsec ^ ((uint64_t)ts.tv_sec << 30) ^ ((uint64_t)getpid() << 16) ^
                  (uint64_t)(uintptr_t)f;
  for (int attempt = 0; attempt < 64; attempt++) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    snprintf(f->temp_path, cap, "%.*s/.%s.%08x.tmp", dir_len == 1 && dir[0] == '/' ? 0 : dir_len,
             dir, base, (unsigned)(seed >> 32));
    f->fd = open(f->temp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (f->fd >= 0) return NBRDF_OK;
    if (errno != EEXIST) break;
  }
  int e = errno;
  char dirbuf[4096];
  snprintf(dirbuf, sizeof dirbuf, "%.*s", dir_len, dir);
  release(f);
  return nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot create a file in '%s': %s", path, dirbuf,
                    strerror(e));
}

nbrdf_status nbrdf_output_file_pwrite(nbrdf_output_file *f, const void *data, size_t n,
                                      long long offset, nbrdf_error *err) {
  const char *p = data;
  while (n > 0) {
    ssize_t w = pwrite(f->fd, p, n, (off_t)offset);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0)
      return nbrdf_fail(err, NBRDF_ERR_IO, "%s: write failed: %s", f->path,
                        w < 0 ? strerror(errno) : "no progress");
    p += w;
    n -= (size_t)w;
    offset += w;
  }
  return NBRDF_OK;
}

nbrdf_status nbrdf_output_file_commit(nbrdf_output_file *f, nbrdf_error *err) {
  nbrdf_status st = NBRDF_OK;
  if (f->fd >= 0) {
    if (fsync(f->fd) != 0 && errno != EINVAL)
      st = nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot flush to disk: %s", f->path, strerror(errno));
    if (close(f->fd) != 0 && st == NBRDF_OK)
      st = nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot close: %s", f->path, strerror(errno));
    f->fd = -1;
  }
  if (st == NBRDF_OK && rename(f->temp_path, f->path) != 0)
    st = nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot rename '%s' into place: %s", f->path,
                    f->temp_path, strerror(errno));
  if (st != NBRDF_OK) unlink(f->temp_path);
  release(f);
  return st;
}

void nbrdf_output_file_abort(nbrdf_output_file *f) {
  if (f->fd >= 0) close(f->fd);
  if (f->temp_path) unlink(f->temp_path);
  release(f);
}
