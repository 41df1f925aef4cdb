/* The trainer (src/train/trainer.c) on a toy fit: a noisy quadratic whose
 * noise comes from PCG32 stream = step plus a generator carried across steps
 * (a word). Its loss falls; a run stopped at any step and resumed ends with
 * the bytes of one that never stopped, its log keeps each row once; options,
 * format and pre-options checkpoints are refused or accepted as documented;
 * progress is throttled and a cancel stops after the current step. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "testing.h"
#include "train/trainer.h"

enum { N = 16 };

typedef struct toy {
  float x[N], grad[N], target[N];
  core_rng carried; /* state across steps: checkpointed as words */
  int reports, cancel_at, legacy_calls;
} toy;

static char *path_of(const char *name) {
  static char buf[4][512];
  static int next;
  char *p = buf[next++ % 4];
  snprintf(p, 512, "%s/%s", testing_tmpdir(), name);
  return p;
}

static nbrdf_status gradient(void *user, int64_t step, double *loss, nbrdf_error *err) {
  (void)err;
  toy *t = user;
  core_rng rng;
  core_rng_init(&rng, 7, (uint64_t)step);
  double sum = 0.0, drift = 0.01 * core_rng_uniform(&t->carried);
  for (int i = 0; i < N; i++) {
    double e = t->x[i] - t->target[i] + 0.05 * (core_rng_uniform(&rng) - 0.5) + drift;
    sum += e * e;
    t->grad[i] = (float)(2.0 * e / N);
  }
  *loss = sum / N;
  return NBRDF_OK;
}

static nbrdf_status report(void *user, trainer *tr, int64_t done, double loss, int flags,
                           nbrdf_error *err) {
  (void)err;
  toy *t = user;
  t->reports++;
  if (done % 10 == 0 || (flags & TRAINER_LAST)) trainer_log(tr, "%lld,%.6g", (long long)done, loss);
  return NBRDF_OK;
}

static nbrdf_status legacy(void *user, const nn_st_reader *r, int64_t *step, nbrdf_error *err) {
  (void)r, (void)err;
  toy *t = user;
  t->legacy_calls++;
  *step = 0;
  return NBRDF_OK;
}

static void toy_init(toy *t) {
  memset(t, 0, sizeof *t);
  for (int i = 0; i < N; i++)
    t->target[i] = (float)(i % 5) - 2.0f;
  core_rng_init(&t->carried, 3, 9);
}

static nbrdf_status toy_run(toy *t, const char *ckpt, const char *log, int64_t steps,
                            int64_t stop_at, const char *options, trainer_result *r,
                            nbrdf_error *err) {
  trainer_group g = {"x", "adam.x.m", "adam.x.v", t->x, t->grad, N, 0.05f, 100, 0.5f};
  trainer_word w[2] = {{"carried.state", &t->carried.state}, {"carried.inc", &t->carried.inc}};
  trainer_options o = TRAINER_OPTIONS_DEFAULT;
  o.steps = steps, o.stop_at_step = stop_at, o.checkpoint = ckpt, o.checkpoint_seconds = 1e9;
  o.format = "toy", o.options = options, o.log_path = log, o.log_header = "step,loss";
  o.stage = "toy";
  trainer_fit fit = {.user = t, .gradient = gradient, .report = report, .legacy = legacy};
  return trainer_run(&o, &fit, &g, 1, NULL, 0, w, 2, r, err);
}

static int count_lines(const char *path) {
  FILE *f = fopen(path, "r");
  int n = 0, c;
  while (f && (c = fgetc(f)) != EOF)
    n += c == '\n';
  if (f) fclose(f);
  return n;
}

static void test_resume_is_exact(void) {
  nbrdf_error err;
  trainer_result r;
  toy a, b;
  toy_init(&a);
  double before = 0.0, after = 0.0;
  gradient(&a, 0, &before, &err);
  toy_init(&a);
  CHECK_OK(toy_run(&a, NULL, path_of("a.csv"), 300, 0, "k=1\n", &r, &err), &err);
  CHECK(r.finished && r.steps_done == 300 && a.reports == 300);
  toy probe = a; /* the loss at the end, without advancing a's generator */
  gradient(&probe, 300, &after, &err);
  CHECK_MSG(after < 0.05 * before, "toy loss %g -> %g", before, after);
  CHECK(count_lines(path_of("a.csv")) == 31);

  /* Stopped at 37, 38 (run twice: the same command resumes), then to the end. */
  toy_init(&b);
  CHECK_FAILS(toy_run(&b, path_of("b.ckpt"), path_of("b.csv"), 300, 37, "k=1\n", &r, &err),
              NBRDF_ERR_CANCELLED, &err, "stopped at step 37 of 300 (checkpointed");
  /* A stop step the checkpoint has passed stops at once, running nothing. */
  toy_init(&b);
  CHECK_FAILS(toy_run(&b, path_of("b.ckpt"), path_of("b.csv"), 300, 10, "k=1\n", &r, &err),
              NBRDF_ERR_CANCELLED, &err, "stopped at step 37 of 300");
  CHECK(b.reports == 0 && r.steps_done == 37);
  toy_init(&b); /* a fresh process: everything comes from the checkpoint */
  CHECK_FAILS(toy_run(&b, path_of("b.ckpt"), path_of("b.csv"), 300, 38, "k=1\n", &r, &err),
              NBRDF_ERR_CANCELLED, &err, "step 38");
  CHECK(r.resumed_from == 37);
  toy_init(&b);
  CHECK_OK(toy_run(&b, path_of("b.ckpt"), path_of("b.csv"), 300, 0, "k=1\n", &r, &err), &err);
  CHECK(r.resumed_from == 38 && r.finished && !r.legacy_resume);
  CHECK_MSG(!memcmp(a.x, b.x, sizeof a.x), "resumed parameters differ");
  CHECK(a.carried.state == b.carried.state);
  /* The log holds every row once (rows after a checkpoint's step are dropped
   * on resume), plus the rows of the two stops (37, 38). */
  CHECK(count_lines(path_of("b.csv")) == 31 + 2);

  /* Options: another value is refused naming the key and both values; one the
   * run lacks too. */
  toy_init(&b);
  CHECK_FAILS(toy_run(&b, path_of("b.ckpt"), NULL, 400, 0, "k=2\n", &r, &err), NBRDF_ERR_MISMATCH,
              &err, "made with k = 1, this run has k = 2");
  CHECK_FAILS(toy_run(&b, path_of("b.ckpt"), NULL, 400, 0, "k=1\nm=3\n", &r, &err),
              NBRDF_ERR_MISMATCH, &err, "m = (unset), this run has m = 3");
  CHECK_FAILS(toy_run(&b, path_of("b.ckpt"), NULL, 400, 0, "", &r, &err), NBRDF_ERR_MISMATCH, &err,
              "this run has k = (unset)");
  CHECK(b.legacy_calls == 0);
}

/* A checkpoint without nbrdf.options goes to the fit's legacy hook. */
static void test_legacy_hook(void) {
  nbrdf_error err;
  nn_st_writer *w = NULL;
  float zero[N] = {0};
  int64_t shape[1] = {N};
  CHECK_OK(nn_st_writer_create(&w, &err), &err);
  CHECK_OK(nn_st_writer_set_metadata(w, "nbrdf.format", "toy", &err), &err);
  CHECK_OK(nn_st_writer_set_metadata(w, "nbrdf.state.carried.state", "5", &err), &err);
  CHECK_OK(nn_st_writer_set_metadata(w, "nbrdf.state.carried.inc", "7", &err), &err);
  const char *names[3] = {"x", "adam.x.m", "adam.x.v"};
  for (int k = 0; k < 3; k++)
    CHECK_OK(nn_st_writer_add(w, names[k], 1, shape, zero, &err), &err);
  CHECK_OK(nn_st_writer_save(w, path_of("old.ckpt"), NULL, &err), &err);
  nn_st_writer_destroy(w);
  toy t;
  toy_init(&t);
  trainer_result r;
  CHECK_OK(toy_run(&t, path_of("old.ckpt"), NULL, 5, 0, "k=1\n", &r, &err), &err);
  CHECK(t.legacy_calls == 1 && r.legacy_resume && r.finished);
  /* Another format is refused, naming both. */
  toy_init(&t);
  trainer_options o = TRAINER_OPTIONS_DEFAULT;
  trainer_group g = {"x", "adam.x.m", "adam.x.v", t.x, t.grad, N, 0.05f, 0, 1.0f};
  o.steps = 10, o.checkpoint = path_of("old.ckpt"), o.format = "other";
  trainer_fit fit = {.user = &t, .gradient = gradient};
  CHECK_FAILS(trainer_run(&o, &fit, &g, 1, NULL, 0, NULL, 0, &r, &err), NBRDF_ERR_MISMATCH, &err,
              "format 'toy', this run writes 'other'");
}

typedef struct progress_count {
  int calls;
  double last_done;
} progress_count;

static int on_progress(void *user, const char *stage, double done, double total) {
  (void)stage, (void)total;
  progress_count *p = user;
  p->calls++;
  p->last_done = done;
  return 0;
}

/* Progress: throttled (a fast run of 2000 steps reports a handful of times,
 * always its end); the cancel flag stops after the current step. */
static void test_progress_and_cancel(void) {
  nbrdf_error err;
  toy t;
  toy_init(&t);
  progress_count pc = {0, 0};
  volatile sig_atomic_t cancel = 0;
  trainer_group g = {"x", "adam.x.m", "adam.x.v", t.x, t.grad, N, 0.05f, 0, 1.0f};
  trainer_options o = TRAINER_OPTIONS_DEFAULT;
  o.steps = 2000, o.progress = on_progress, o.user = &pc, o.cancel = &cancel;
  trainer_fit fit = {.user = &t, .gradient = gradient, .report = report};
  trainer_result r;
  CHECK_OK(trainer_run(&o, &fit, &g, 1, NULL, 0, NULL, 0, &r, &err), &err);
  CHECK_MSG(pc.calls >= 2 && pc.calls < 200 && pc.last_done == 2000, "%d calls, last %g", pc.calls,
            pc.last_done);
  cancel = 1;
  toy_init(&t);
  CHECK_FAILS(trainer_run(&o, &fit, &g, 1, NULL, 0, NULL, 0, &r, &err), NBRDF_ERR_CANCELLED, &err,
              "stopped at step 1 of 2000");
  CHECK(t.reports == 1);
}

int main(void) {
  RUN(test_resume_is_exact);
  RUN(test_legacy_hook);
  RUN(test_progress_and_cancel);
  return testing_finish();
}
