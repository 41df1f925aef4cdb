/* Data set files: thread-independent bytes, resume, cancellation, corruption,
 * and values that agree with nbrdf_brdf_eval within the reported errors. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "testing.h"
#include "train/dataset.h"

static train_dataset_settings tiny(train_kind kind) {
  train_dataset_settings s = TRAIN_DATASET_SETTINGS_DEFAULT;
  s.kind = kind;
  s.count = 5;
  s.seed = 11;
  s.incident = 2;
  s.outgoing = 16;
  s.sampled = 8;
  s.spp = 256;
  s.threads = 1;
  return s;
}

static char *path_of(const char *name) {
  static char buf[4][512];
  static int next;
  char *p = buf[next++ % 4];
  snprintf(p, 512, "%s/%s", testing_tmpdir(), name);
  return p;
}

static unsigned char *slurp(const char *path, long *n) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  *n = ftell(f);
  fseek(f, 0, SEEK_SET);
  unsigned char *b = malloc((size_t)*n + 1);
  if (fread(b, 1, (size_t)*n, f) != (size_t)*n) *n = -1;
  fclose(f);
  return b;
}

static int same_file(const char *a, const char *b) {
  long na = 0, nb = 0; /* slurp leaves them unset when it cannot open the file */
  unsigned char *x = slurp(a, &na), *y = slurp(b, &nb);
  int same = x && y && na == nb && na > 0 && memcmp(x, y, (size_t)na) == 0;
  free(x), free(y);
  return same;
}

static void write_bytes(const char *path, const unsigned char *b, long n) {
  FILE *f = fopen(path, "wb");
  fwrite(b, 1, (size_t)n, f);
  fclose(f);
}

static void test_threads_and_resume(void) {
  train_dataset_settings s = tiny(TRAIN_LAYERED2);
  nbrdf_error err;
  const char *a = path_of("a.nbds"), *b = path_of("b.nbds"), *c = path_of("c.nbds");
  unlink(a), unlink(b), unlink(c);
  CHECK_OK(train_dataset_write(a, &s, NULL, &err), &err);
  s.threads = 2;
  CHECK_OK(train_dataset_write(b, &s, NULL, &err), &err);
  CHECK_MSG(same_file(a, b), "1 and 2 threads give different bytes");
  train_dataset_info info;
  CHECK_OK(train_dataset_read(a, 1, &info, NULL, NULL, &err), &err);
  CHECK(info.complete && info.records == 5);

  /* Cut in the middle of record 2, and just before the footer: resuming
   * gives the identical file. */
  long n;
  unsigned char *bytes = slurp(a, &n);
  long cuts[2] = {64 + (long)(2.5 * (double)(n - 64 - 24) / 5.0), n - 24};
  for (int i = 0; i < 2; i++) {
    write_bytes(c, bytes, cuts[i]);
    uint64_t resumed = 99;
    CHECK_OK(train_dataset_write(c, &s, &resumed, &err), &err);
    CHECK(resumed == (i == 0 ? 2u : 5u));
    CHECK_MSG(same_file(a, c), "resume after a cut at %ld differs", cuts[i]);
  }
  /* A complete file is left alone. */
  uint64_t resumed = 0;
  CHECK_OK(train_dataset_write(c, &s, &resumed, &err), &err);
  CHECK(resumed == 5 && same_file(a, c));
  /* Other settings refuse to resume. */
  train_dataset_settings other = s;
  other.spp = 128;
  CHECK_FAILS(train_dataset_write(c, &other, NULL, &err), NBRDF_ERR_MISMATCH, &err, "spp 256");
  free(bytes);
}

/* Slower than the library's progress throttle (0.1 s), so that every tick
 * reaches it: the start, before BRDF 0, before BRDF 1 (stop). */
static int stop_at_third(void *user, const char *stage, double done, double total) {
  (void)stage, (void)done, (void)total;
  int *calls = user;
  struct timespec pause = {0, 110000000};
  nanosleep(&pause, NULL);
  return ++*calls >= 3;
}

static void test_cancel_then_resume(void) {
  train_dataset_settings s = tiny(TRAIN_CONDUCTOR);
  s.count = 9;
  nbrdf_error err;
  const char *a = path_of("d.nbds"), *b = path_of("e.nbds");
  unlink(a), unlink(b);
  CHECK_OK(train_dataset_write(a, &s, NULL, &err), &err);
  int calls = 0;
  s.progress = stop_at_third, s.user = &calls;
  CHECK_FAILS(train_dataset_write(b, &s, NULL, &err), NBRDF_ERR_CANCELLED, &err, "resume");
  train_dataset_info info;
  CHECK_OK(train_dataset_read(b, 0, &info, NULL, NULL, &err), &err);
  /* stopped inside the first batch (4 BRDFs, 1 thread): the finished BRDF 0 is kept */
  CHECK_MSG(info.records == 1 && !info.complete, "%llu records", (unsigned long long)info.records);
  s.progress = NULL;
  uint64_t resumed = 0;
  CHECK_OK(train_dataset_write(b, &s, &resumed, &err), &err);
  CHECK(resumed == 1 && same_file(a, b));
}

static void test_corruption_refused(void) {
  train_dataset_settings s = tiny(TRAIN_DIELECTRIC);
  nbrdf_error err;
  const char *a = path_of("f.nbds"), *c = path_of("g.nbds");
  unlink(a);
  CHECK_OK(train_dataset_write(a, &s, NULL, &err), &err);
  long n;
  unsigned char *bytes = slurp(a, &n);
  long rec = (n - 64 - 24) / 5;
  long where[3] = {20, 64 + 3 * rec + 200, n - 3};
  const char *needle[3] = {"header", "record 3", "footer"};
  for (int i = 0; i < 3; i++) {
    bytes[where[i]] ^= 0x10;
    write_bytes(c, bytes, n);
    bytes[where[i]] ^= 0x10;
    train_dataset_info info;
    CHECK_FAILS(train_dataset_read(c, 1, &info, NULL, NULL, &err), NBRDF_ERR_FORMAT, &err,
                needle[i]);
  }
  /* Non-strict reading keeps the valid prefix. */
  bytes[where[1]] ^= 0x10;
  write_bytes(c, bytes, n);
  train_dataset_info info;
  CHECK_OK(train_dataset_read(c, 0, &info, NULL, NULL, &err), &err);
  CHECK(info.records == 3 && !info.complete);
  /* A truncated file is incomplete, not valid. */
  write_bytes(c, bytes, n - 24);
  CHECK_FAILS(train_dataset_read(c, 1, &info, NULL, NULL, &err), NBRDF_ERR_FORMAT, &err,
              "record 3");
  free(bytes);
}

typedef struct agree {
  train_kind kind;
  int n, outliers;
  double z2;
  double sum_ds, sum_ev, var;
} agree;

static int check_against_eval(void *user, const train_dataset_record *r) {
  agree *a = user;
  nbrdf_brdf *b = NULL;
  nbrdf_error err;
  CHECK_OK(train_params_create(&r->params, &b, &err), &err);
  if (!b) return 1;
  for (size_t j = 0; j < r->n_samples; j++) {
    const float *x = r->samples + TRAIN_DATASET_FLOATS * j;
    nbrdf_query q = {{x[0], x[1], x[2]}, {x[3], x[4], x[5]}};
    double len_i = sqrt(q.wi[0] * q.wi[0] + q.wi[1] * q.wi[1] + q.wi[2] * q.wi[2]);
    double len_o = sqrt(q.wo[0] * q.wo[0] + q.wo[1] * q.wo[1] + q.wo[2] * q.wo[2]);
    for (int d = 0; d < 3; d++)
      q.wi[d] /= len_i, q.wo[d] /= len_o;
    nbrdf_eval_options o = {1234u + j, 2048, 1};
    double f, se;
    CHECK_OK(nbrdf_brdf_eval(b, 1, &q, &o, &f, &se, &err), &err);
    if (a->kind == TRAIN_CONDUCTOR) {
      CHECK_REL(x[6], f, 1e-5, 1e-6);
      CHECK(x[7] == 0.0f);
    } else {
      double s = sqrt((double)x[7] * x[7] + se * se);
      double z = (x[6] - f) / fmax(s, 1e-9 * fmax(f, 1e-3));
      a->z2 += z * z;
      a->outliers += fabs(z) > 4.0;
      a->sum_ds += x[6], a->sum_ev += f, a->var += s * s;
    }
    a->n++;
  }
  nbrdf_brdf_destroy(b);
  return 0;
}

static void test_values_agree_with_eval(void) {
  for (int kind = TRAIN_CONDUCTOR; kind <= TRAIN_LAYERED2; kind += TRAIN_LAYERED2) {
    train_dataset_settings s = tiny((train_kind)kind);
    s.count = 3;
    s.spp = 1024;
    nbrdf_error err;
    const char *a = path_of("h.nbds");
    unlink(a);
    CHECK_OK(train_dataset_write(a, &s, NULL, &err), &err);
    agree ag = {(train_kind)kind, 0, 0, 0.0, 0.0, 0.0, 0.0};
    train_dataset_info info;
    CHECK_OK(train_dataset_read(a, 1, &info, check_against_eval, &ag, &err), &err);
    CHECK(ag.n == 3 * 2 * 16);
    if (kind == TRAIN_LAYERED2) {
      printf("layered2: %d values, mean z^2 %.3g, sums %.6g vs %.6g +- %.3g\n", ag.n, ag.z2 / ag.n,
             ag.sum_ds, ag.sum_ev, sqrt(ag.var));
      CHECK_MSG(ag.outliers <= 1, "%d of %d values beyond 4 standard errors", ag.outliers, ag.n);
      CHECK_MSG(ag.z2 / ag.n < 2.0, "mean z^2 = %g", ag.z2 / ag.n);
      CHECK_MSG(fabs(ag.sum_ds - ag.sum_ev) < 4.0 * sqrt(ag.var), "sums %g vs %g", ag.sum_ds,
                ag.sum_ev);
    }
  }
}

/* --draws coverage: a version-2 file that reads back with its draws, whose
 * records are the coverage parameters, and that refuses a Table 2 resume;
 * Table 2 files stay version 1. */
static void test_coverage_file(void) {
  train_dataset_settings s = tiny(TRAIN_LAYERED2);
  s.kind = TRAIN_DIELECTRIC;
  s.draws = TRAIN_DRAWS_COVERAGE;
  s.count = 40;
  nbrdf_error err = {0};
  const char *path = path_of("coverage.nbds");
  CHECK_OK(train_dataset_write(path, &s, NULL, &err), &err);
  train_dataset_info info;
  CHECK_OK(train_dataset_read(path, 1, &info, NULL, NULL, &err), &err);
  CHECK(info.complete && info.settings.draws == TRAIN_DRAWS_COVERAGE);
  long n = 0;
  unsigned char *b = slurp(path, &n);
  CHECK(b && n > 12 && b[8] == 2);
  free(b);
  train_dataset_settings t = s;
  t.draws = TRAIN_DRAWS_TABLE2;
  CHECK_FAILS(train_dataset_write(path, &t, NULL, &err), NBRDF_ERR_MISMATCH, &err,
              "draws coverage");
  const char *p1 = path_of("table2.nbds");
  CHECK_OK(train_dataset_write(p1, &t, NULL, &err), &err);
  b = slurp(p1, &n);
  CHECK(b && n > 12 && b[8] == 1);
  free(b);
}

static void test_bad_settings(void) {
  train_dataset_settings s = tiny(TRAIN_LAYERED2);
  nbrdf_error err;
  s.spp = 1;
  CHECK_FAILS(train_dataset_write(path_of("i.nbds"), &s, NULL, &err), NBRDF_ERR_ARGUMENT, &err,
              "spp");
  s = tiny(TRAIN_LAYERED2);
  s.sampled = 17;
  CHECK_FAILS(train_dataset_write(path_of("i.nbds"), &s, NULL, &err), NBRDF_ERR_ARGUMENT, &err,
              "sampled");
  CHECK(access(path_of("i.nbds"), F_OK) != 0);
}

int main(void) {
  RUN(test_threads_and_resume);
  RUN(test_cancel_then_resume);
  RUN(test_corruption_refused);
  RUN(test_values_agree_with_eval);
  RUN(test_coverage_file);
  RUN(test_bad_settings);
  return testing_finish();
}
