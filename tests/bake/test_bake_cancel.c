/* Cancel and progress reach inside a band of a bake (issue 15, item 11): with
 * the default model, one band of 256 x 256 all-distinct texels costs seconds
 * of network time; progress must move within it, a cancel from the callback
 * or from a signal handler's flag must return NBRDF_ERR_CANCELLED within a few
 * chunks of work, and no file or temporary may be left.
 *
 * Measured in work, not seconds (issue 30, part 3): the process's CPU time
 * (CLOCK_PROCESS_CPUTIME_ID) after the cancel must be at most ALLOWED_ROWS rows'
 * worth, a row's cost measured in the same run from the progress reports. Waiting
 * for a CPU on a loaded machine, or a sanitizer build's slower instructions (they
 * slow the calibration alike), cannot fail it. A chunk of the networks is 2,048
 * tuples: 8 rows of 256. */
#include <dirent.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <time.h>

#include "core/progress.h"
#include "nbrdf/bake.h"
#include "testing.h"
#include "texture/oiio_shim.h"

#define SIZE 256 /* 65,536 texels: one band, 32 chunks of the networks */
#define ALLOWED_ROWS 32.0 /* 4 chunks of the networks: the one in flight and margin */
#define SLACK_CPU_S 0.02  /* unwinding: abort the file, free the band */

/* CPU seconds of the whole process: does not advance while it waits for a CPU. */
static double cpu_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts); /* async-signal-safe */
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU seconds per row of this run's bake, from test_cancel_from_callback. */
static double row_cpu = -1.0;

static nbrdf_model *model;
static char tmp[512];

static const char *path(const char *name) {
  static char buf[8][640];
  static int k;
  k = (k + 1) % 8;
  snprintf(buf[k], sizeof buf[k], "%s/%s", tmp, name);
  return buf[k];
}

static int left_nothing(void) {
  struct stat sb;
  if (stat(path("out.exr"), &sb) == 0) return 0;
  DIR *d = opendir(tmp);
  if (!d) return 0;
  int clean = 1;
  struct dirent *e;
  while ((e = readdir(d)))
    if (strstr(e->d_name, ".tmp")) clean = 0;
  closedir(d);
  return clean;
}

static nbrdf_bake_inputs inputs(void) {
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  in.param[NBRDF_BAKE_ALPHA1].path = path("alpha1.exr");
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ETA], 1.5f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_ALPHA2], 0.3f);
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_R0], 0.8f);
  in.param[NBRDF_BAKE_ALBEDO].path = path("albedo.exr");
  nbrdf_bake_param_constant(&in.param[NBRDF_BAKE_SIGMA_T], 2.0f);
  return in;
}

static void write_maps(void) {
  nbrdf_error e, *err = &e;
  static float a[SIZE * SIZE], b[SIZE * SIZE];
  for (int i = 0; i < SIZE * SIZE; i++) { /* every texel its own tuple */
    a[i] = 0.05f + 0.8f * (float)i / (SIZE * SIZE);
    b[i] = 0.9f - 0.8f * (float)((i * 7919) % (SIZE * SIZE)) / (SIZE * SIZE);
  }
  CHECK_OK(texture_image_write(path("alpha1.exr"), SIZE, SIZE, 1, a, NBRDF_PIXEL_FLOAT, err), err);
  CHECK_OK(texture_image_write(path("albedo.exr"), SIZE, SIZE, 1, b, NBRDF_PIXEL_FLOAT, err), err);
}

typedef struct watch {
  int calls, inside, monotonic;
  double last_done, cancelled_at;
  double first_cpu, first_done; /* the first report inside the band */
} watch;

/* Cancels at the fourth report from inside the band (0 < done < SIZE): the first
 * and the last give a row's CPU cost. */
static int cancel_inside(void *user, const char *stage, double done, double total) {
  watch *w = user;
  w->calls++;
  /* The bake's rows and the energy audit of each band share one count of rows. */
  if (done < w->last_done || total != SIZE || (strcmp(stage, "bake") && strcmp(stage, "audit")))
    w->monotonic = 0;
  w->last_done = done;
  if (done > 0 && done < SIZE && ++w->inside == 1) w->first_cpu = cpu_now(), w->first_done = done;
  if (w->inside < 4) return 0;
  w->cancelled_at = cpu_now();
  if (done > w->first_done) row_cpu = (w->cancelled_at - w->first_cpu) / (done - w->first_done);
  return 1;
}

static void test_cancel_from_callback(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = inputs();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  watch w = {0, 0, 1, 0.0, 0.0, 0.0, 0.0};
  o.progress = cancel_inside;
  o.user = &w;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("out.exr"), NULL, err), NBRDF_ERR_CANCELLED, err,
              "cancelled");
  double after = cpu_now() - w.cancelled_at;
  CHECK_MSG(w.inside >= 4, "%d progress reports inside the band", w.inside);
  CHECK_MSG(w.monotonic, "progress went backwards or named another stage/total");
  CHECK_MSG(row_cpu > 0, "no row cost measured (done did not move inside the band)");
  CHECK_MSG(after <= ALLOWED_ROWS * row_cpu + SLACK_CPU_S,
            "%.3f CPU-s after the callback cancelled: %.1f rows of %.4f CPU-s (allowed %g)", after,
            after / row_cpu, row_cpu, ALLOWED_ROWS);
  CHECK(left_nothing());
  printf("  cancel from the callback: %d reports inside the band, %.3f CPU-s after it (%.1f rows "
         "of %.4f CPU-s)\n",
         w.inside, after, row_cpu > 0 ? after / row_cpu : 0.0, row_cpu);
}

static volatile sig_atomic_t flag;
static double flag_set_at;

static void on_alarm(int sig) {
  (void)sig;
  flag_set_at = cpu_now();
  flag = 1;
}

/* The CLI's case: a signal handler sets the flag while the networks run. */
static void test_cancel_from_signal(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = inputs();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  flag = 0;
  o.cancel = &flag;
  struct sigaction sa, old;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_alarm;
  sigaction(SIGPROF, &sa, &old);
  /* 0.4 CPU-s of the process (ITIMER_PROF), not of the clock: after the gather, inside the
   * networks however loaded the machine. */
  struct itimerval it = {{0, 0}, {0, 400000}};
  setitimer(ITIMER_PROF, &it, NULL);
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("out.exr"), NULL, err), NBRDF_ERR_CANCELLED, err,
              "cancelled");
  double after = cpu_now() - flag_set_at;
  struct itimerval off = {{0, 0}, {0, 0}};
  setitimer(ITIMER_PROF, &off, NULL);
  sigaction(SIGPROF, &old, NULL);
  CHECK_MSG(flag, "the bake finished before the timer went off");
  if (row_cpu > 0)
    CHECK_MSG(after <= ALLOWED_ROWS * row_cpu + SLACK_CPU_S,
              "%.3f CPU-s after the flag was set: %.1f rows of %.4f CPU-s (allowed %g)", after,
              after / row_cpu, row_cpu, ALLOWED_ROWS);
  CHECK(left_nothing());
  printf("  cancel from a signal handler's flag: %.3f CPU-s after it (%.1f rows)\n", after,
         row_cpu > 0 ? after / row_cpu : 0.0);
}

int main(void) {
  nbrdf_error e, *err = &e;
  snprintf(tmp, sizeof tmp, "%s", testing_tmpdir());
  char bundle[1024];
  snprintf(bundle, sizeof bundle, "%s/models/default", testing_source_dir());
  CHECK_OK(nbrdf_model_load(bundle, &model, err), err);
  if (!model) return testing_finish();
  write_maps();
  RUN(test_cancel_from_callback);
  RUN(test_cancel_from_signal);
  nbrdf_model_destroy(model);
  return testing_finish();
}
