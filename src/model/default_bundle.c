/* Where the default model bundle is: $NBRDF_BUNDLE, the install prefix, the source tree, the
 * current directory (include/nbrdf/model.h). One place for the library and every CLI command. */
#define _GNU_SOURCE /* dladdr */
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "nbrdf/model.h"

#ifndef NBRDF_SOURCE_DIR
#define NBRDF_SOURCE_DIR "."
#endif
#ifndef NBRDF_BUNDLE_FROM_LIBDIR
#define NBRDF_BUNDLE_FROM_LIBDIR "../share/nbrdf/models/default"
#endif
#ifndef NBRDF_BUNDLE_FROM_BINDIR
#define NBRDF_BUNDLE_FROM_BINDIR "../share/nbrdf/models/default"
#endif

#define TRIED_MAX 4

static int is_dir(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
}

static int holds_bundle(const char *dir) {
  char json[PATH_MAX + 16];
  struct stat sb;
  if (snprintf(json, sizeof json, "%s/model.json", dir) >= (int)sizeof json) return 0;
  return stat(json, &sb) == 0 && S_ISREG(sb.st_mode);
}

/* `rel` joined to the folder of the file `file`, made canonical; 0 when it does not exist. */
static int beside(const char *file, const char *rel, char out[PATH_MAX]) {
  char dir[PATH_MAX], joined[2 * PATH_MAX];
  if (!file || snprintf(dir, sizeof dir, "%s", file) >= (int)sizeof dir) return 0;
  char *slash = strrchr(dir, '/');
  if (!slash) return 0;
  *slash = '\0';
  snprintf(joined, sizeof joined, "%s/%s", dir, rel);
  return realpath(joined, out) != NULL;
}

static nbrdf_status found(char *path, size_t size, const char *dir, nbrdf_error *err) {
  if (strlen(dir) >= size)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "default bundle %s: path longer than %zu bytes", dir,
                     size - 1);
  memcpy(path, dir, strlen(dir) + 1);
  return NBRDF_OK;
}

nbrdf_status nbrdf_default_bundle_path(char *path, size_t size, nbrdf_error *err) {
  if (!path || size == 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "default bundle: no room for the path");
  const char *env = getenv("NBRDF_BUNDLE");
  if (env && env[0]) {
    if (!is_dir(env))
      return core_fail(err, NBRDF_ERR_IO, "$NBRDF_BUNDLE=%s: %s", env,
                       errno == ENOENT ? "no such folder" : "not a folder");
    if (!holds_bundle(env))
      return core_fail(err, NBRDF_ERR_FORMAT, "$NBRDF_BUNDLE=%s: no model.json in it", env);
    return found(path, size, env, err);
  }

  /* The installed bundle, relative to the loaded library and to the executable: both, since
   * a statically linked program's "library" is the executable itself. */
  char installed[2][PATH_MAX];
  const char *tried[TRIED_MAX];
  int n_tried = 0;
  Dl_info info;
  if (dladdr((void *)nbrdf_default_bundle_path, &info) && info.dli_fname &&
      beside(info.dli_fname, NBRDF_BUNDLE_FROM_LIBDIR, installed[0])) {
    if (holds_bundle(installed[0])) return found(path, size, installed[0], err);
    tried[n_tried++] = installed[0];
  }
  char exe[PATH_MAX];
  ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (len > 0) {
    exe[len] = '\0';
    if (beside(exe, NBRDF_BUNDLE_FROM_BINDIR, installed[1]) &&
        (n_tried == 0 || strcmp(installed[1], installed[0]) != 0)) {
      if (holds_bundle(installed[1])) return found(path, size, installed[1], err);
      tried[n_tried++] = installed[1];
    }
  }
  static const char *const fixed[] = {NBRDF_SOURCE_DIR "/models/default", "models/default"};
  for (int i = 0; i < 2; i++) {
    if (holds_bundle(fixed[i])) return found(path, size, fixed[i], err);
    tried[n_tried++] = fixed[i];
  }
  core_fail(err, NBRDF_ERR_IO, "no default model bundle found ($NBRDF_BUNDLE is not set; tried");
  for (int i = 0; i < n_tried && err; i++) {
    size_t used = strlen(err->message);
    snprintf(err->message + used, sizeof err->message - used, "%s %s", i ? "," : "", tried[i]);
  }
  if (err) {
    size_t used = strlen(err->message);
    snprintf(err->message + used, sizeof err->message - used, ")");
  }
  return NBRDF_ERR_IO;
}

nbrdf_status nbrdf_model_load_default(nbrdf_model **out, char *path_used, size_t size,
                                      nbrdf_error *err) {
  char dir[PATH_MAX];
  if (out) *out = NULL;
  nbrdf_status st = nbrdf_default_bundle_path(dir, sizeof dir, err);
  if (st != NBRDF_OK) return st;
  if (path_used && size > 0) snprintf(path_used, size, "%s", dir);
  st = nbrdf_model_load(dir, out, err);
  if (st != NBRDF_OK && getenv("NBRDF_BUNDLE") && getenv("NBRDF_BUNDLE")[0])
    core_error_prefix(err, "$NBRDF_BUNDLE=%s: ", dir);
  return st;
}
