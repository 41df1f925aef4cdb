/* Cancel and progress reach inside a band of a bake (issue 15, item 11): with
 * the default model, one band of 256 x 256 all-distinct texels costs seconds
 * of network time; progress must move within it, a cancel from the callback
 * or from a signal handler's flag must return NBRDF_ERR_CANCELLED quickly
 * (bound 3 s: the promise is 1 s, with margin for a loaded 2-core machine),
 * and no file or temporary may be left. */
#include <dirent.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/time.h>

#include "core/progress.h"
#include "nbrdf/bake.h"
#include "testing.h"
#include "texture/oiio_shim.h"

#define SIZE 256 /* 65,536 texels: one band, 32 chunks of the networks */

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
} watch;

/* Cancels at the second report from inside the band (0 < done < SIZE). */
static int cancel_inside(void *user, const char *stage, double done, double total) {
  watch *w = user;
  w->calls++;
  if (done < w->last_done || total != SIZE || strcmp(stage, "bake")) w->monotonic = 0;
  w->last_done = done;
  if (done > 0 && done < SIZE) w->inside++;
  if (w->inside < 2) return 0;
  w->cancelled_at = core_monotonic_seconds();
  return 1;
}

static void test_cancel_from_callback(void) {
  nbrdf_error e, *err = &e;
  nbrdf_bake_inputs in = inputs();
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  watch w = {0, 0, 1, 0.0, 0.0};
  o.progress = cancel_inside;
  o.user = &w;
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("out.exr"), NULL, err), NBRDF_ERR_CANCELLED, err,
              "cancelled");
  double latency = core_monotonic_seconds() - w.cancelled_at;
  CHECK_MSG(w.inside >= 2, "%d progress reports inside the band", w.inside);
  CHECK_MSG(w.monotonic, "progress went backwards or named another stage/total");
  CHECK_MSG(latency < 3.0, "returned %.2f s after the callback cancelled", latency);
  CHECK(left_nothing());
  printf("  cancel from the callback: %d reports inside the band, returned in %.3f s\n", w.inside,
         latency);
}

static volatile sig_atomic_t flag;
static double flag_set_at;

static void on_alarm(int sig) {
  (void)sig;
  flag_set_at = core_monotonic_seconds(); /* clock_gettime is async-signal-safe */
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
  sigaction(SIGALRM, &sa, &old);
  struct itimerval it = {{0, 0}, {0, 400000}}; /* 0.4 s: after the gather, inside the networks */
  setitimer(ITIMER_REAL, &it, NULL);
  CHECK_FAILS(nbrdf_bake(model, &in, &o, path("out.exr"), NULL, err), NBRDF_ERR_CANCELLED, err,
              "cancelled");
  double latency = core_monotonic_seconds() - flag_set_at;
  sigaction(SIGALRM, &old, NULL);
  CHECK_MSG(flag, "the bake finished before the timer went off");
  CHECK_MSG(latency < 3.0, "returned %.2f s after the flag was set", latency);
  CHECK(left_nothing());
  printf("  cancel from a signal handler's flag: returned in %.3f s\n", latency);
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
