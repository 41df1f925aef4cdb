#define _GNU_SOURCE /* O_TMPFILE, linkat's AT_SYMLINK_FOLLOW */
#include "core/output_file.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <time.h>
#include <unistd.h>

#include "core/error.h"

#define TEMP_SUFFIX ".tmp"
#define TEMP_HEX 8
/* The longest part of the destination's name a temporary name repeats: ".", that part,
 * ".XXXXXXXX.tmp" fit NAME_MAX, so a destination of up to NAME_MAX bytes can be replaced. */
#define TEMP_BASE_MAX (NAME_MAX - 2 - TEMP_HEX - (int)(sizeof TEMP_SUFFIX - 1))

static void release(core_output_file *f) {
  free(f->path);
  free(f->temp_path);
  f->path = f->temp_path = NULL;
  f->proc_path[0] = '\0';
  f->fd = -1;
  f->keep_mode = 0;
}

/* Root passes access() whatever the mode bits say, so the bits are checked too:
 * a file someone made 0444 is meant not to change. */
static int read_only(const char *path, const struct stat *sb) {
  return (sb->st_mode & 0222) == 0 || access(path, W_OK) != 0;
}

/* The directory part of `path` ("." when none) in a new string. */
static char *dir_of(const char *path) {
  const char *slash = strrchr(path, '/');
  if (!slash) return strdup(".");
  if (slash == path) return strdup("/");
  return strndup(path, (size_t)(slash - path));
}

static int read_only_fs(const char *path) {
  struct statvfs vfs;
  return statvfs(path, &vfs) == 0 && (vfs.f_flag & ST_RDONLY);
}

/* Whether a file can be put at `path` at all: its folder exists, takes new files (a rename
 * or link needs that, also over an existing file) and its name fits. Checked before a
 * command's work, so that a typo in a folder costs nothing (it used to fail after it). */
static nbrdf_status check_place(const char *path, nbrdf_error *err) {
  char *dir = dir_of(path);
  if (!dir) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  const char *slash = strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  nbrdf_status st = NBRDF_OK;
  /* Worded as the creation's own failure would be (core_output_file_open). */
  struct stat sb;
  int e = 0;
  if (stat(dir, &sb) != 0)
    e = errno;
  else if (!S_ISDIR(sb.st_mode))
    e = ENOTDIR;
  else if (read_only_fs(dir))
    e = EROFS;
  else if (access(dir, W_OK | X_OK) != 0)
    e = errno;
  if (e)
    st = core_fail(err, NBRDF_ERR_IO, "%s: cannot create a file in '%s': %s", path, dir,
                   strerror(e));
  if (st == NBRDF_OK) {
    long name_max = pathconf(dir, _PC_NAME_MAX);
    if (name_max <= 0) name_max = NAME_MAX;
    if ((long)strlen(base) > name_max)
      st = core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s: the name is %zu bytes long; this file system allows %ld (%s)", path,
                     strlen(base), name_max, strerror(ENAMETOOLONG));
  }
  free(dir);
  return st;
}

nbrdf_status core_output_check(const char *path, const char *const *inputs, int n_inputs,
                               nbrdf_error *err) {
  if (!path || !path[0]) return core_fail(err, NBRDF_ERR_ARGUMENT, "output path is empty");
  struct stat out;
  if (stat(path, &out) != 0) { /* a new file cannot be an input */
    int e = errno;
    nbrdf_status st = check_place(path, err);
    if (st == NBRDF_OK && e != ENOENT) /* ELOOP, EACCES, ENOTDIR and such */
      st = core_fail(err, NBRDF_ERR_IO, "%s: %s", path, strerror(e));
    return st;
  }
  if (S_ISDIR(out.st_mode)) return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: is a directory", path);
  for (int i = 0; i < n_inputs; i++) {
    struct stat in;
    if (!inputs[i] || stat(inputs[i], &in) != 0) continue;
    if (in.st_dev == out.st_dev && in.st_ino == out.st_ino)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "%s: the output is the input '%s'; refusing to overwrite an input", path,
                       inputs[i]);
  }
  if (!S_ISREG(out.st_mode))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s: exists and is not a regular file (a device, FIFO or socket); refusing "
                     "to replace it",
                     path);
  /* Before the mode bits: on a read-only mount "make it writable" cannot help. */
  if (read_only_fs(path))
    return core_fail(err, NBRDF_ERR_IO, "%s: the file system is read-only (%s)", path,
                     strerror(EROFS));
  if (read_only(path, &out))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s: exists and is read-only; refusing to replace it (make it writable or "
                     "remove it first)",
                     path);
  return check_place(path, err);
}

/* Seconds since the epoch at which this process started: now less the time since its start
 * (its start and the uptime both count from boot, in /proc), so no boot-time rounding enters.
 * Now when /proc cannot tell. */
static double process_start(void) {
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  double now = (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
  FILE *fp = fopen("/proc/self/stat", "r");
  if (!fp) return now;
  char buf[1024];
  size_t n = fread(buf, 1, sizeof buf - 1, fp);
  fclose(fp);
  buf[n] = '\0';
  char *p = strrchr(buf, ')'); /* the command name may hold spaces */
  unsigned long long ticks = 0;
  /* p + 1 is the space before field 3; the loop stops at the one before field 22 (starttime). */
  for (int field = 3; p && field <= 22; field++)
    p = strchr(p + 1, ' ');
  if (!p || sscanf(p + 1, "%llu", &ticks) != 1) return now;
  double uptime = -1;
  fp = fopen("/proc/uptime", "r");
  if (!fp) return now;
  if (fscanf(fp, "%lf", &uptime) != 1) uptime = -1;
  fclose(fp);
  long hz = sysconf(_SC_CLK_TCK);
  if (uptime < 0 || hz <= 0) return now;
  double age = uptime - (double)ticks / (double)hz;
  return age > 0 ? now - age : now;
}

static int is_temp_name(const char *name) {
  size_t n = strlen(name), tail = 1 + TEMP_HEX + strlen(TEMP_SUFFIX);
  if (name[0] != '.' || n < 2 + tail || strcmp(name + n - strlen(TEMP_SUFFIX), TEMP_SUFFIX) != 0)
    return 0;
  const char *hex = name + n - tail;
  if (hex[0] != '.') return 0;
  for (int i = 1; i <= TEMP_HEX; i++)
    if (!((hex[i] >= '0' && hex[i] <= '9') || (hex[i] >= 'a' && hex[i] <= 'f'))) return 0;
  return 1;
}

#define STALE_MARGIN_S 2.0

/* Removes what a killed writer left in `dir`: files named like our temporary
 * files, ours, older than this process and not locked by a live writer. */
static void remove_stale_temps(const char *dir) {
  DIR *d = opendir(dir);
  if (!d) return;
  /* /proc's uptime and start ticks have 10 ms steps: a process a few ms old may
   * compute its start as now. The margin keeps a file made just before this
   * process (another writer's, not yet locked) from counting as stale. */
  double start = process_start() - STALE_MARGIN_S;
  uid_t me = geteuid();
  int dfd = dirfd(d);
  struct dirent *e;
  while ((e = readdir(d)) != NULL) {
    if (!is_temp_name(e->d_name)) continue;
    struct stat sb;
    if (fstatat(dfd, e->d_name, &sb, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(sb.st_mode) ||
        sb.st_uid != me || (double)sb.st_mtim.tv_sec + 1e-9 * (double)sb.st_mtim.tv_nsec >= start)
      continue;
    int fd = openat(dfd, e->d_name, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) continue;
    if (flock(fd, LOCK_EX | LOCK_NB) == 0) unlinkat(dfd, e->d_name, 0);
    close(fd);
  }
  closedir(d);
}

/* "dir/.base.XXXXXXXX.tmp" with a fresh random part in `out` (size `cap`). The seed mixes
 * the clock, the process and the caller's address: no shared counter between threads. */
static void temp_name(char *out, size_t cap, const char *dir, const char *base, uint64_t *seed) {
  *seed = *seed * 6364136223846793005ULL + 1442695040888963407ULL;
  snprintf(out, cap, "%s/.%.*s.%08x" TEMP_SUFFIX, strcmp(dir, "/") == 0 ? "" : dir, TEMP_BASE_MAX,
           base, (unsigned)(*seed >> 32));
}

static uint64_t temp_seed(const void *salt) {
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return (uint64_t)ts.tv_nsec ^ ((uint64_t)ts.tv_sec << 30) ^ ((uint64_t)getpid() << 16) ^
         (uint64_t)(uintptr_t)salt;
}

/* The destination exists: its mode bits (and owner where allowed) go to the temporary file. */
static void carry_mode(int fd, const struct stat *sb) {
  struct stat mine;
  if (fstat(fd, &mine) == 0 && (mine.st_uid != sb->st_uid || mine.st_gid != sb->st_gid)) {
    if (fchown(fd, sb->st_uid, sb->st_gid) != 0 && fchown(fd, (uid_t)-1, sb->st_gid) != 0) {
      /* not permitted: the file becomes ours, as any new file would */
    }
  }
  (void)fchmod(fd, sb->st_mode & 0777);
}

nbrdf_status core_output_file_open_flags(core_output_file *f, const char *path,
                                         const char *const *inputs, int n_inputs, int flags,
                                         nbrdf_error *err) {
  f->path = f->temp_path = NULL;
  f->proc_path[0] = '\0';
  f->fd = -1;
  f->keep_mode = 0;
  if (!path || !path[0]) return core_fail(err, NBRDF_ERR_ARGUMENT, "output path is empty");
  const char *slash = strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  if (!base[0] || strcmp(base, ".") == 0 || strcmp(base, "..") == 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: is a directory", path);
  nbrdf_status st = core_output_check(path, inputs, n_inputs, err);
  if (st != NBRDF_OK) return st;
  struct stat existing;
  int exists = stat(path, &existing) == 0;

  const char *env = getenv("NBRDF_OUTPUT_NAMED_TEMP");
  if (env && env[0] == '1') flags |= NBRDF_OUTPUT_NAMED_TEMP;
  char *dir = dir_of(path);
  size_t cap = strlen(path) + 32;
  f->path = strdup(path);
  f->temp_path = malloc(cap);
  if (!dir || !f->path || !f->temp_path) {
    free(dir);
    release(f);
    return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  }
  remove_stale_temps(dir);

  int e = 0;
  if (!(flags & NBRDF_OUTPUT_NAMED_TEMP)) {
    f->fd = open(dir, O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    if (f->fd >= 0) {
      snprintf(f->proc_path, sizeof f->proc_path, "/proc/self/fd/%d", f->fd);
      if (access(f->proc_path, F_OK) != 0) { /* no /proc: it could never be linked */
        close(f->fd);
        f->fd = -1;
        f->proc_path[0] = '\0';
      }
    } else if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL) {
      e = errno;
    }
  }
  if (f->fd >= 0) {
    free(f->temp_path);
    f->temp_path = NULL;
  } else if (!e) {
    uint64_t seed = temp_seed(f);
    for (int attempt = 0; attempt < 64; attempt++) {
      temp_name(f->temp_path, cap, dir, base, &seed);
      f->fd = open(f->temp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (f->fd >= 0 || errno != EEXIST) break;
    }
    if (f->fd < 0) e = errno;
  }
  if (f->fd < 0) {
    core_fail(err, NBRDF_ERR_IO, "%s: cannot create a file in '%s': %s", path, dir, strerror(e));
    free(dir);
    release(f);
    return NBRDF_ERR_IO;
  }
  free(dir);
  /* The lock tells remove_stale_temps that a live writer owns the file. */
  (void)flock(f->fd, LOCK_EX | LOCK_NB);
  if (exists) {
    carry_mode(f->fd, &existing);
    f->keep_mode = 1;
  }
  return NBRDF_OK;
}

nbrdf_status core_output_file_open(core_output_file *f, const char *path, const char *const *inputs,
                                   int n_inputs, nbrdf_error *err) {
  return core_output_file_open_flags(f, path, inputs, n_inputs, 0, err);
}

const char *core_output_file_name(const core_output_file *f) {
  return f->temp_path ? f->temp_path : f->proc_path;
}

nbrdf_status core_output_file_pwrite(core_output_file *f, const void *data, size_t n,
                                     long long offset, nbrdf_error *err) {
  const char *p = data;
  while (n > 0) {
    ssize_t w = pwrite(f->fd, p, n, (off_t)offset);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0)
      return core_fail(err, NBRDF_ERR_IO, "%s: write failed: %s", f->path,
                       w < 0 ? strerror(errno) : "no progress");
    p += w;
    n -= (size_t)w;
    offset += w;
  }
  return NBRDF_OK;
}

/* Links the unnamed temporary file to the destination: directly when there is
 * none, else under a temporary name renamed over it. */
static int link_unnamed(core_output_file *f) {
  struct stat sb;
  if (lstat(f->path, &sb) != 0 && errno == ENOENT) {
    if (linkat(AT_FDCWD, f->proc_path, AT_FDCWD, f->path, AT_SYMLINK_FOLLOW) == 0) return 0;
    if (errno != EEXIST) return -1;
  }
  char *dir = dir_of(f->path);
  const char *slash = strrchr(f->path, '/');
  size_t cap = strlen(f->path) + 32;
  char *tmp = malloc(cap);
  if (!dir || !tmp) {
    free(dir), free(tmp);
    errno = ENOMEM;
    return -1;
  }
  uint64_t seed = temp_seed(f);
  int rc = -1;
  for (int attempt = 0; attempt < 64; attempt++) {
    temp_name(tmp, cap, dir, slash ? slash + 1 : f->path, &seed);
    rc = linkat(AT_FDCWD, f->proc_path, AT_FDCWD, tmp, AT_SYMLINK_FOLLOW);
    if (rc == 0 || errno != EEXIST) break;
  }
  if (rc == 0 && rename(tmp, f->path) != 0) {
    int e = errno;
    unlink(tmp);
    errno = e;
    rc = -1;
  }
  free(dir), free(tmp);
  return rc;
}

nbrdf_status core_output_file_commit(core_output_file *f, nbrdf_error *err) {
  nbrdf_status st = NBRDF_OK;
  if (f->fd < 0) {
    core_output_file_abort(f);
    return core_fail(err, NBRDF_ERR_ARGUMENT, "output: commit without an open file");
  }
  if (fsync(f->fd) != 0 && errno != EINVAL)
    st = core_fail(err, NBRDF_ERR_IO, "%s: cannot flush to disk: %s", f->path, strerror(errno));
  /* The destination may have been replaced by a FIFO or made read-only meanwhile. */
  if (st == NBRDF_OK) st = core_output_check(f->path, NULL, 0, err);
  /* Renamed before closing: the lock is held until the name is gone. */
  if (st == NBRDF_OK && f->temp_path && rename(f->temp_path, f->path) != 0)
    st = core_fail(err, NBRDF_ERR_IO, "%s: cannot rename '%s' into place: %s", f->path,
                   f->temp_path, strerror(errno));
  if (st == NBRDF_OK && !f->temp_path && link_unnamed(f) != 0)
    st = core_fail(err, NBRDF_ERR_IO, "%s: cannot put the written file in place: %s", f->path,
                   strerror(errno));
  if (close(f->fd) != 0 && st == NBRDF_OK)
    st = core_fail(err, NBRDF_ERR_IO, "%s: cannot close: %s", f->path, strerror(errno));
  f->fd = -1;
  if (st != NBRDF_OK && f->temp_path) unlink(f->temp_path);
  release(f);
  return st;
}

nbrdf_status core_output_file_commit_all(core_output_file *files, int n, nbrdf_error *err) {
  nbrdf_status st = NBRDF_OK;
  /* Everything that can fail for one file and not another comes first, while every
   * destination is still as it was. */
  for (int i = 0; st == NBRDF_OK && i < n; i++) {
    if (files[i].fd < 0)
      st = core_fail(err, NBRDF_ERR_ARGUMENT, "output: commit without an open file");
    else if (fsync(files[i].fd) != 0 && errno != EINVAL)
      st = core_fail(err, NBRDF_ERR_IO, "%s: cannot flush to disk: %s", files[i].path,
                     strerror(errno));
    else
      st = core_output_check(files[i].path, NULL, 0, err);
  }
  int placed = 0;
  char **fresh = calloc((size_t)(n > 0 ? n : 1), sizeof *fresh); /* new files placed so far */
  if (st == NBRDF_OK && !fresh) st = core_fail(err, NBRDF_ERR_MEMORY, "output: out of memory");
  for (; st == NBRDF_OK && placed < n; placed++) {
    char *path = files[placed].keep_mode ? NULL : strdup(files[placed].path);
    st = core_output_file_commit(&files[placed], err);
    if (st == NBRDF_OK) fresh[placed] = path;
    else free(path);
  }
  if (st != NBRDF_OK) {
    for (int i = 0; i < n; i++)
      core_output_file_abort(&files[i]);
    /* A rename failing after others succeeded (rare: the checks above passed) takes the new
     * files back; a replaced file's old bytes are gone and cannot be. */
    for (int i = 0; fresh && i < placed; i++)
      if (fresh[i]) unlink(fresh[i]);
  }
  for (int i = 0; fresh && i < n; i++)
    free(fresh[i]);
  free(fresh);
  return st;
}

void core_output_file_abort(core_output_file *f) {
  if (f->temp_path) unlink(f->temp_path);
  if (f->fd >= 0) close(f->fd);
  release(f);
}

nbrdf_status core_output_file_write_all(const char *path, const void *data, size_t n,
                                        const char *const *inputs, int n_inputs, nbrdf_error *err) {
  core_output_file f;
  nbrdf_status st = core_output_file_open(&f, path, inputs, n_inputs, err);
  if (st != NBRDF_OK) return st;
  st = core_output_file_pwrite(&f, data, n, 0, err);
  if (st != NBRDF_OK) {
    core_output_file_abort(&f);
    return st;
  }
  return core_output_file_commit(&f, err);
}
