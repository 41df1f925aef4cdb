#include "model/files.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"

#define FILES_PATH_MAX 4096
#define FILES_SIZE_MAX ((size_t)1 << 31)

nbrdf_status model_read_file(const char *path, char **bytes, size_t *size, nbrdf_error *err) {
  FILE *fp = fopen(path, "rb");
  if (!fp) return nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  char *buf = NULL;
  size_t len = 0, cap = 0;
  nbrdf_status st = NBRDF_OK;
  for (;;) {
    if (len == cap) {
      cap = cap ? 2 * cap : (size_t)1 << 16;
      char *grown = cap <= FILES_SIZE_MAX ? realloc(buf, cap + 1) : NULL;
      if (!grown) {
        st = nbrdf_fail(err, NBRDF_ERR_MEMORY, "%s: too large or out of memory", path);
        break;
      }
      buf = grown;
    }
    size_t got = fread(buf + len, 1, cap - len, fp);
    len += got;
    if (got == 0) {
      if (ferror(fp)) st = nbrdf_fail(err, NBRDF_ERR_IO, "%s: read error", path);
      break;
    }
  }
  fclose(fp);
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
  char path[FILES_PATH_MAX], tmp[FILES_PATH_MAX + 16];
  int n = snprintf(path, sizeof path, "%s/%s", dir, file);
  if (n < 0 || n >= (int)sizeof path)
    return nbrdf_fail(err, NBRDF_ERR_ARGUMENT, "%s: path too long", dir);
  snprintf(tmp, sizeof tmp, "%s.XXXXXX", path);
  int fd = mkstemp(tmp);
  if (fd < 0) return nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
  FILE *fp = fdopen(fd, "wb");
  if (!fp) {
    close(fd);
    unlink(tmp);
    return nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
  }
  size_t len = strlen(text);
  int ok = fwrite(text, 1, len, fp) == len;
  ok = fflush(fp) == 0 && ok;
  ok = fsync(fileno(fp)) == 0 && ok;
  ok = fclose(fp) == 0 && ok;
  /* mkstemp creates 0600; a bundle is meant to be shared like any other file. */
  mode_t mask = umask(0);
  umask(mask);
  if (ok) ok = chmod(tmp, 0666 & ~mask) == 0;
  if (ok) ok = rename(tmp, path) == 0;
  if (!ok) {
    int e = errno;
    unlink(tmp);
    return nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot write: %s", path, strerror(e));
  }
  return NBRDF_OK;
}

nbrdf_status model_make_dirs(const char *dir, nbrdf_error *err) {
  char path[FILES_PATH_MAX];
  int n = snprintf(path, sizeof path, "%s", dir);
  if (n <= 0 || n >= (int)sizeof path)
    return nbrdf_fail(err, NBRDF_ERR_ARGUMENT, "folder name empty or too long");
  for (char *p = path + 1;; p++) {
    if (*p == '/' || *p == '\0') {
      char c = *p;
      *p = '\0';
      if (mkdir(path, 0777) != 0 && errno != EEXIST)
        return nbrdf_fail(err, NBRDF_ERR_IO, "%s: cannot create the folder: %s", path,
                          strerror(errno));
      *p = c;
      if (c == '\0') break;
    }
  }
  struct stat sb;
  if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode))
    return nbrdf_fail(err, NBRDF_ERR_IO, "%s: not a folder", dir);
  return NBRDF_OK;
}
