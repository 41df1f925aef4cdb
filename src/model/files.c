#include "model/files.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "core/output_file.h"

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
  char path[FILES_PATH_MAX];
  int n = snprintf(path, sizeof path, "%s/%s", dir, file);
  if (n < 0 || n >= (int)sizeof path)
    return nbrdf_fail(err, NBRDF_ERR_ARGUMENT, "%s: path too long", dir);
  return nbrdf_output_file_write_all(path, text, strlen(text), NULL, 0, err);
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
