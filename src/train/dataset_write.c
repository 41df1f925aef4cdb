/* Writing and resuming a data set file (train/dataset.h, docs/DATASET.md). */
#include <errno.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/error.h"
#include "core/output_file.h"
#include "core/progress.h"
#include "nn/safetensors.h"
#include "train/dataset.h"
#include "train/dataset_format.h"

static int same_settings(const train_dataset_settings *a, const train_dataset_settings *b) {
  return a->kind == b->kind && a->draws == b->draws && a->count == b->count && a->seed == b->seed &&
         a->incident == b->incident && a->outgoing == b->outgoing && a->sampled == b->sampled &&
         a->spp == b->spp;
}

/* Opens `path` positioned after its valid prefix (creating it with a header
 * when absent); *done and *sum describe that prefix. */
static nbrdf_status open_output(const char *path, const train_dataset_settings *s, FILE **out,
                                uint64_t *done, uint64_t *sum, int *complete, nbrdf_error *err) {
  *done = 0, *complete = 0;
  /* Appended in place (a stopped run resumes from the valid prefix), so not through a
   * temporary file; the destination is still checked like every output's. */
  nbrdf_status checked = core_output_check(path, NULL, 0, err);
  if (checked != NBRDF_OK) return checked;
  if (access(path, F_OK) == 0) {
    train_dataset_info info;
    nbrdf_status st = train_dataset_read(path, 0, &info, NULL, NULL, err);
    if (st) {
      core_error_prefix(err, "cannot resume (delete the file to start again): ");
      return st;
    }
    if (!same_settings(&info.settings, s))
      return core_fail(
          err, NBRDF_ERR_MISMATCH,
          "%s: exists with other settings (kind %s, draws %s, count %llu, seed %llu, "
          "incident %d, outgoing %d, sampled %d, spp %d); delete it or use them",
          path, train_kind_name(info.settings.kind), train_draws_name(info.settings.draws),
          (unsigned long long)info.settings.count, (unsigned long long)info.settings.seed,
          info.settings.incident, info.settings.outgoing, info.settings.sampled, info.settings.spp);
    *done = info.records, *sum = info.prefix_checksum, *complete = info.complete;
    if (info.complete) return NBRDF_OK;
    /* Drop a partial or corrupt tail record before appending. */
    if (truncate(path, (off_t)info.valid_bytes) != 0)
      return core_fail(err, NBRDF_ERR_IO, "%s: cannot truncate to its valid prefix", path);
    *out = fopen(path, "r+b");
    if (!*out || fseek(*out, (long)info.valid_bytes, SEEK_SET) != 0) {
      if (*out) fclose(*out);
      return core_fail(err, NBRDF_ERR_IO, "%s: cannot open for appending", path);
    }
    return NBRDF_OK;
  }
  unsigned char head[TRAIN_DS_HEADER_BYTES];
  train_ds_encode_header(s, head);
  *out = fopen(path, "wb");
  if (!*out) return core_fail(err, NBRDF_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
  if (fwrite(head, 1, sizeof head, *out) != sizeof head || fflush(*out) != 0) {
    fclose(*out);
    return core_fail(err, NBRDF_ERR_IO, "%s: cannot write the header", path);
  }
  *sum = nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, head, sizeof head);
  return NBRDF_OK;
}

/* The calling thread's ticker, asked from inside its BRDF's random walks. */
typedef struct batch_tick {
  core_ticker *tk;
  const train_dataset_settings *s;
  uint64_t first;
  int *made;
  volatile sig_atomic_t *halt;
} batch_tick;

static int batch_tick_fn(void *user) {
  batch_tick *b = user;
  int m;
#pragma omp atomic read
  m = *b->made;
  if (core_ticker_tick(b->tk, "dataset", (double)(b->first + (uint64_t)m), (double)b->s->count, 0))
    *b->halt = 1;
  return *b->halt;
}

/* Generates BRDFs [first, first + n) into recs (n records of rb bytes);
 * ok[k] is set for each record made. The calling thread (0 of the team) asks
 * the ticker between its BRDFs and between chunks of a layered BRDF's walks
 * (one layered BRDF takes seconds under load); once it says stop, every
 * thread's walks stop, the unfinished BRDFs are dropped and *stopped is set:
 * the caller keeps the records made in order. */
static nbrdf_status generate_batch(const train_dataset_settings *s, uint64_t first, int n,
                                   int threads, unsigned char *recs, float *samples,
                                   size_t per_thread, core_ticker *tk, unsigned char *ok,
                                   int *stopped, nbrdf_error *err) {
  size_t rb = train_ds_record_bytes(s);
  nbrdf_status st = NBRDF_OK;
  volatile sig_atomic_t halt = 0;
  int made = 0;
  batch_tick bt = {tk, s, first, &made, &halt};
  const brdf_layered_lobe_hook caller = {&halt, batch_tick_fn, &bt}, others = {&halt, NULL, NULL};
  memset(ok, 0, (size_t)n);
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
  for (int k = 0; k < n; k++) {
    int h, m;
#pragma omp atomic read
    h = halt;
    if (!h && omp_get_thread_num() == 0) {
#pragma omp atomic read
      m = made;
      if (core_ticker_tick(tk, "dataset", (double)(first + (uint64_t)m), (double)s->count, 0)) {
#pragma omp atomic write
        halt = 1;
        h = 1;
      }
    }
    if (h) continue;
    float *mine = samples + (size_t)omp_get_thread_num() * per_thread;
    train_params p;
    nbrdf_error e;
    nbrdf_status sk = train_dataset_generate_one(
        s, first + (uint64_t)k, omp_get_thread_num() == 0 ? &caller : &others, &p, mine, &e);
    if (sk == NBRDF_OK) {
      train_ds_encode_record(s, first + (uint64_t)k, &p, mine, recs + (size_t)k * rb);
      ok[k] = 1;
#pragma omp atomic update
      made++;
    }
#pragma omp critical(train_dataset_error)
    if (sk != NBRDF_OK && sk != NBRDF_ERR_CANCELLED && st == NBRDF_OK) {
      st = sk;
      if (err) *err = e;
    }
  }
  *stopped = halt;
  return st;
}

nbrdf_status train_dataset_write(const char *path, const train_dataset_settings *s,
                                 uint64_t *resumed_from, nbrdf_error *err) {
  if (!path || !s) return core_fail(err, NBRDF_ERR_ARGUMENT, "dataset: NULL path or settings");
  if (s->count < 1) return core_fail(err, NBRDF_ERR_ARGUMENT, "dataset: count must be >= 1");
  nbrdf_status st = train_dataset_check_settings(s, err);
  if (st) return st;
  FILE *f = NULL;
  uint64_t done = 0, sum = 0;
  int complete;
  st = open_output(path, s, &f, &done, &sum, &complete, err);
  if (resumed_from) *resumed_from = done;
  if (st || complete) return st;

  int threads = s->threads > 0 ? s->threads : omp_get_max_threads();
  int batch = 4 * threads;
  size_t rb = train_ds_record_bytes(s);
  size_t per_thread = (size_t)s->incident * (size_t)s->outgoing * TRAIN_DATASET_FLOATS;
  unsigned char *recs = malloc((size_t)batch * rb), *ok = malloc((size_t)batch);
  float *samples = malloc((size_t)threads * per_thread * sizeof *samples);
  core_ticker tk;
  core_ticker_init(&tk, s->progress, s->user, NULL);
  if (!recs || !ok || !samples) {
    st = core_fail(err, NBRDF_ERR_MEMORY, "dataset: out of memory for a batch of %d", batch);
    goto done;
  }
  if (core_ticker_tick(&tk, "dataset", (double)done, (double)s->count, 1)) {
    st = core_fail(err, NBRDF_ERR_CANCELLED,
                   "%s: stopped at %llu of %llu BRDFs; run again to resume", path,
                   (unsigned long long)done, (unsigned long long)s->count);
    goto done;
  }
  while (done < s->count) {
    int n = s->count - done < (uint64_t)batch ? (int)(s->count - done) : batch;
    int stopped = 0;
    st = generate_batch(s, done, n, threads, recs, samples, per_thread, &tk, ok, &stopped, err);
    if (st) goto done;
    if (stopped) /* keep the records made in order: a later run resumes after them */
      for (int k = 0; k < n; k++)
        if (!ok[k]) {
          n = k;
          break;
        }
    if (fwrite(recs, rb, (size_t)n, f) != (size_t)n || fflush(f) != 0) {
      st = core_fail(err, NBRDF_ERR_IO, "%s: write failed after %llu records: %s", path,
                     (unsigned long long)done, strerror(errno));
      goto done;
    }
    sum = nn_st_fnv1a64(sum, recs, (size_t)n * rb);
    done += (uint64_t)n;
    if ((stopped ||
         core_ticker_tick(&tk, "dataset", (double)done, (double)s->count, done == s->count)) &&
        done < s->count) {
      st = core_fail(err, NBRDF_ERR_CANCELLED,
                     "%s: stopped at %llu of %llu BRDFs; run again to resume", path,
                     (unsigned long long)done, (unsigned long long)s->count);
      goto done;
    }
  }
  unsigned char foot[TRAIN_DS_FOOTER_BYTES];
  train_ds_encode_footer(s->count, sum, foot);
  if (fwrite(foot, 1, sizeof foot, f) != sizeof foot || fflush(f) != 0)
    st = core_fail(err, NBRDF_ERR_IO, "%s: cannot write the footer", path);
done:
  free(recs), free(ok), free(samples);
  if (fclose(f) != 0 && !st) st = core_fail(err, NBRDF_ERR_IO, "%s: close failed", path);
  return st;
}
