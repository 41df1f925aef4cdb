#include "model/files.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "core/output_file.h"
#include "core/input_file.h"

#define FILES_PATH_MAX 4096
#define FILES_SIZE_MAX ((size_t)1 << 31)

nbrdf_status model_read_file(const char *path, uint64_t max_bytes, char **bytes, size_t *size,
                             nbrdf_error *err) {
  /* Regular files only, sized by stat before the buffer is allocated: a
   * bundle file symlinked to /dev/zero would otherwise grow to the cap. */
  int fd = -1;
  uint64_t n = 0;
  if (max_bytes > FILES_SIZE_MAX) max_bytes = FILES_SIZE_MAX;
  nbrdf_status st = core_input_open(path, max_bytes, &fd, &n, err);
  if (st != NBRDF_OK) return st;
  char *buf = malloc((size_t)n + 1);
  if (!buf) {
    close(fd);
    return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory for %llu bytes", path,
                     (unsigned long long)n);
  }
  size_t len = 0;
  while (len < n) {
    ssize_t got = read(fd, buf + len, (size_t)n - len);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      st = got < 0 ? core_fail(err, NBRDF_ERR_IO, "%s: read error: %s", path, strerror(errno))
                   : core_fail(err, NBRDF_ERR_IO, "%s: file shrank while being read", path);
      break;
    }
    len += (size_t)got;
  }
  close(fd);
  if (st != NBRDF_OK) {
    free(buf);
    return st;
  }
  buf[len] = '\0';
  *bytes = buf;
  *size = len;
  return NBRDF_OK;
}

nbrdf_status model_write_text_file(const char *dir, const char *file, const char *text,
                                   nbrdf_error *err) {
  char path[FILES_PATH_MAX];
  int n = snprintf(path, sizeof path, "%s/%s", dir, file);
  if (n < 0 || n >= (int)sizeof path)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: path too long", dir);
  return core_output_file_write_all(path, text, strlen(text), NULL, 0, err);
}

nbrdf_status model_make_dirs(const char *dir, nbrdf_error *err) {
  char path[FILES_PATH_MAX];
  int n = snprintf(path, sizeof path, "%s", dir);
  if (n <= 0 || n >= (int)sizeof path)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "folder name empty or too long");
  for (char *p = path + 1;; p++) {
    if (*p == '/' || *p == '\0') {
      char c = *p;
      *p = '\0';
      if (mkdir(path, 0777) != 0 && errno != EEXIST)
        return core_fail(err, NBRDF_ERR_IO, "%s: cannot create the folder: %s", path,
                         strerror(errno));
      *p = c;
      if (c == '\0') break;
    }
  }
  struct stat sb;
  if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode))
    return core_fail(err, NBRDF_ERR_IO, "%s: not a folder", dir);
  return NBRDF_OK;
}
