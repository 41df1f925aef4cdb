/* A learned albedo screen for the energy audit (docs/notes/2026-11-29-audit-head.md): a tiny
 * regression network ("head") from a tuple's six normalised parameters u (or its latent) to
 * the audit's value (bake_albedo_precise: the polar rule's maximum over the six angles),
 * trained here on measured tuples. A tuple would be cleared when head + M <= BAKE_AUDIT_LIMIT,
 * M the largest under-prediction (true - head) on independent draws times a safety factor.
 * Nothing in the library uses it: this measures whether such an M is small enough to clear
 * the materials that make the audit cost.
 *
 *   bench_audit_head [--bundle DIR] [--train N,N..] [--width W,W..] [--input params|latent,..]
 *                    [--steps S] [--under K] [--safety F] [--draw N] [--seed S]
 *                    [--corner-p P] [--probe-m X] [--cache DIR]
 *                    [--material NAME BAKE-ARGS...]...
 *
 * Training set (seed S): half uniform over the normalised range, stratified over the audit's
 * (alpha1, alpha2) regions as bench_audit_margin's bases; a quarter the --sharp clearcoat
 * family of bench_audit_margin (alpha1 at the range's low end, eta 1.45, albedo 0.8,
 * sigma_t 1, alpha2 and r0 in its upper half drawn); a quarter "corners" (each parameter at
 * one of its range's ends with probability P, 0.2, else uniform). Held-out: the three
 * families again with seed S + 1000, --draw (8,192) tuples each. Measured values are cached
 * under --cache (/tmp/nbrdf-audit-head), keyed by a hash of the latents, so reruns train only.
 * The head: LINEAR(W) ReLU LINEAR(W) ReLU LINEAR(1) on inputs standardised by the training
 * set, Adam, batch 256, S steps (20,000; learning rate 3e-3 halved every fifth), loss
 * w r^2 with r = true - head and w = K (--under, 4) where r > 0 (under-prediction), else 1.
 *
 * --material NAME followed by `nbrdf bake` maps arguments (--alpha1 .. --sigma-t, and
 * --roughness alpha|perceptual; range clamp) gathers the maps' distinct tuples as the bake
 * does (bake_gather_tuples), measures all of them (cached), and per head prints the share
 * the head clears, true - head there, the head's CPU seconds, and what the audit
 * (bake_audit_tuples) measures on all tuples against on those the head leaves; the same
 * with the margin --probe-m X (0.08; 0: not), with how many of the draws' tuples above the
 * limit a head with that margin would clear (wrongly). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bake/bake_audit.h"
#include "bake/bake_select.h"
#include "bake/bake_sources.h"
#include "bake/bake_tuple.h"
#include "bench_clock.h"
#include "core/error.h"
#include "core/rng.h"
#include "model/bundle.h"
#include "model/material.h"
#include "nbrdf/bake.h"
#include "nn/nn.h"

enum { P = NBRDF_BAKE_PARAM_COUNT, R = BAKE_AUDIT_REGIONS, BATCH = 256, MAX_MAT = 4 };
/* bake_band.c's chunk of tuples per bake_audit_tuples call. */
enum { AUDIT_CHUNK = 64 };
enum { WHOLE, SHARP, CORNER, N_KIND };
static const char *kind_name[N_KIND] = {"whole range", "sharp clearcoat", "corners"};

/* A set of tuples with their latents and measured values. */
typedef struct set {
  size_t n;
  int D;
  bake_tuple *t;
  float *u;   /* [n x P] normalised */
  float *out; /* [n x (D + 2)] latent, sigma, w */
  float *lat; /* [n x D] */
  double *y;  /* [n] the audit's value */
} set;

typedef struct ctx {
  const nbrdf_model *model;
  float lo[P], hi[P];
  int D;
  const char *cache;
  double measure_cpu; /* CPU seconds spent measuring (not cached) */
} ctx;

static int fail(const nbrdf_error *err) {
  fprintf(stderr, "bench_audit_head: %s\n", err->message);
  return 1;
}

static void draw(const ctx *c, int kind, size_t n, uint64_t seed, double corner_p, bake_tuple *t) {
  core_rng rng;
  core_rng_init(&rng, seed, (uint64_t)kind);
  for (size_t b = 0; b < n; b++) {
    double u[P];
    for (int id = 0; id < P; id++)
      u[id] = core_rng_uniform(&rng);
    u[NBRDF_BAKE_ALPHA1] = ((double)(b % R) + u[NBRDF_BAKE_ALPHA1]) / R;
    u[NBRDF_BAKE_ALPHA2] = ((double)(b / R % R) + u[NBRDF_BAKE_ALPHA2]) / R;
    if (kind == SHARP) { /* bench_audit_margin --sharp */
      u[NBRDF_BAKE_ALPHA1] = 0.0;
      u[NBRDF_BAKE_ETA] = model_material_normalise(c->lo, c->hi, NBRDF_BAKE_ETA, 1.45f);
      u[NBRDF_BAKE_ALBEDO] = model_material_normalise(c->lo, c->hi, NBRDF_BAKE_ALBEDO, 0.8f);
      u[NBRDF_BAKE_SIGMA_T] = model_material_normalise(c->lo, c->hi, NBRDF_BAKE_SIGMA_T, 1.0f);
      u[NBRDF_BAKE_R0] = 0.5 + 0.5 * u[NBRDF_BAKE_R0];
    } else if (kind == CORNER) {
      for (int id = 0; id < P; id++)
        if (core_rng_uniform(&rng) < corner_p) u[id] = core_rng_uniform(&rng) < 0.5 ? 0.0 : 1.0;
    }
    for (int id = 0; id < P; id++)
      t[b].p[id] = model_material_unnormalise(c->lo, c->hi, id, u[id]);
  }
}

static uint64_t fnv(const void *p, size_t bytes, uint64_t h) {
  const unsigned char *s = p;
  for (size_t i = 0; i < bytes; i++)
    h = (h ^ s[i]) * UINT64_C(0x100000001b3);
  return h;
}

/* Latents of s->t, then the measured values: from the cache when a file for these latents
 * exists, else measured and written (temp file, renamed). */
static nbrdf_status complete(ctx *c, set *s, nbrdf_error *err) {
  const size_t n = s->n;
  const int D = s->D = c->D;
  s->u = malloc(n * P * sizeof *s->u), s->out = malloc(n * (D + 2) * sizeof *s->out);
  s->lat = malloc(n * D * sizeof *s->lat), s->y = malloc(n * sizeof *s->y);
  if (!s->u || !s->out || !s->lat || !s->y)
    return core_fail(err, NBRDF_ERR_MEMORY, "out of memory for %zu tuples", n);
  nbrdf_status st = bake_tuples_evaluate(c->model, s->t, NULL, n, s->out, err);
  if (st != NBRDF_OK) return st;
  for (size_t k = 0; k < n; k++) {
    memcpy(s->lat + k * D, s->out + k * (D + 2), D * sizeof *s->lat);
    for (int id = 0; id < P; id++)
      s->u[k * P + id] = model_material_normalise(c->lo, c->hi, id, s->t[k].p[id]);
  }
  uint64_t h = fnv(s->lat, n * D * sizeof *s->lat, UINT64_C(0xcbf29ce484222325));
  char path[512], tmp[520];
  snprintf(path, sizeof path, "%s/y-%016llx-%zu.bin", c->cache, (unsigned long long)h, n);
  FILE *f = fopen(path, "rb");
  if (f) {
    size_t got = fread(s->y, sizeof *s->y, n, f);
    int extra = fgetc(f);
    fclose(f);
    if (got == n && extra == EOF) return NBRDF_OK;
  }
  double c0 = bench_cpu_seconds();
  st = bake_albedo_precise(c->model, NULL, n, s->lat, NULL, s->y, NULL, err);
  c->measure_cpu += bench_cpu_seconds() - c0;
  if (st != NBRDF_OK) return st;
  mkdir(c->cache, 0777);
  snprintf(tmp, sizeof tmp, "%s.tmp", path);
  f = fopen(tmp, "wb");
  if (f && fwrite(s->y, sizeof *s->y, n, f) == n && fclose(f) == 0)
    rename(tmp, path);
  else if (f)
    fclose(f);
  return NBRDF_OK;
}

static void set_free(set *s) {
  free(s->t), free(s->u), free(s->out), free(s->lat), free(s->y);
  memset(s, 0, sizeof *s);
}

/* The training set: half WHOLE, a quarter SHARP, a quarter CORNER. */
static nbrdf_status make_train(ctx *c, size_t n, uint64_t seed, double corner_p, set *s,
                               nbrdf_error *err) {
  const size_t part[N_KIND] = {n / 2, n / 4, n - n / 2 - n / 4};
  s->n = n;
  s->t = calloc(n, sizeof *s->t);
  if (!s->t) return core_fail(err, NBRDF_ERR_MEMORY, "out of memory for %zu tuples", n);
  for (int k = 0, at = 0; k < N_KIND; at += (int)part[k], k++)
    draw(c, k, part[k], seed, corner_p, s->t + at);
  return complete(c, s, err);
}

/* ---------------------------------------------------------------------------- the head -- */

typedef struct head {
  int latent, I, W;
  float mean[64], scale[64];
  nn_network *nn;
  nn_workspace *infer;
} head;

static const float *head_input(const head *h, const set *s, size_t k) {
  return h->latent ? s->lat + k * s->D : s->u + k * P;
}

static void standardise(const head *h, const float *x, float *z) {
  for (int i = 0; i < h->I; i++)
    z[i] = (x[i] - h->mean[i]) * h->scale[i];
}

/* head(x) of n tuples of s into pred[n]. */
static nbrdf_status head_predict(head *h, const set *s, size_t n, const size_t *idx, double *pred,
                                 nbrdf_error *err) {
  enum { CH = 4096 };
  static float x[CH * 64], y[CH];
  for (size_t k0 = 0; k0 < n; k0 += CH) {
    int m = (int)(n - k0 < CH ? n - k0 : CH);
    for (int j = 0; j < m; j++)
      standardise(h, head_input(h, s, idx ? idx[k0 + j] : k0 + j), x + (size_t)j * h->I);
    nbrdf_status st = nn_forward(h->nn, h->infer, x, m, y, err);
    if (st != NBRDF_OK) return st;
    for (int j = 0; j < m; j++)
      pred[k0 + j] = y[j];
  }
  return NBRDF_OK;
}

static nbrdf_status head_train(head *h, const set *s, int steps, double under, uint64_t seed,
                               double *cpu, nbrdf_error *err) {
  const size_t n = s->n;
  for (int i = 0; i < h->I; i++) { /* standardisation from the training set */
    double m = 0.0, v = 0.0;
    for (size_t k = 0; k < n; k++)
      m += head_input(h, s, k)[i];
    m /= (double)n;
    for (size_t k = 0; k < n; k++)
      v += (head_input(h, s, k)[i] - m) * (head_input(h, s, k)[i] - m);
    v /= (double)n;
    h->mean[i] = (float)m, h->scale[i] = (float)(1.0 / sqrt(v + 1e-12));
  }
  nn_spec spec;
  nn_spec_init(&spec, h->I);
  nn_spec_add(&spec, NBRDF_NN_LINEAR, h->W);
  nn_spec_add(&spec, NBRDF_NN_RELU, 0);
  nn_spec_add(&spec, NBRDF_NN_LINEAR, h->W);
  nn_spec_add(&spec, NBRDF_NN_RELU, 0);
  nn_spec_add(&spec, NBRDF_NN_LINEAR, 1);
  nn_workspace *ws = NULL;
  nn_adam *adam = NULL;
  nbrdf_status st = nn_create(&spec, &h->nn, err);
  if (st == NBRDF_OK) st = nn_workspace_create(h->nn, BATCH, NBRDF_NN_TRAIN, &ws, err);
  if (st == NBRDF_OK) st = nn_workspace_create(h->nn, 4096, NBRDF_NN_INFER, &h->infer, err);
  nn_adam_options ao = NBRDF_ADAM_OPTIONS_DEFAULT;
  ao.lr = 3e-3f, ao.decay_every = steps / 5 > 0 ? steps / 5 : 1, ao.decay_gamma = 0.5f;
  const size_t np = h->nn ? nn_param_count(h->nn) : 0;
  if (st == NBRDF_OK) st = nn_adam_create(np, &ao, &adam, err);
  float *grad = malloc(np * sizeof *grad);
  size_t *perm = malloc(n * sizeof *perm);
  if (st == NBRDF_OK && (!grad || !perm)) st = core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
  if (st != NBRDF_OK) {
    free(grad), free(perm), nn_workspace_destroy(ws), nn_adam_destroy(adam);
    return st;
  }
  nn_init_params(h->nn, seed);
  core_rng rng;
  core_rng_init(&rng, seed, 99);
  static float x[BATCH * 64], y[BATCH], dy[BATCH];
  size_t at = n;
  double c0 = bench_cpu_seconds();
  for (int step = 0; st == NBRDF_OK && step < steps; step++) {
    memset(grad, 0, np * sizeof *grad);
    for (int j = 0; j < BATCH; j++) {
      if (at == n) { /* a new epoch: Fisher-Yates */
        for (size_t k = 0; k < n; k++)
          perm[k] = k;
        for (size_t k = n - 1; k > 0; k--) {
          size_t r = core_rng_u32(&rng) % (k + 1), tmp = perm[k];
          perm[k] = perm[r], perm[r] = tmp;
        }
        at = 0;
      }
      size_t k = perm[at++];
      standardise(h, head_input(h, s, k), x + (size_t)j * h->I);
      dy[j] = (float)s->y[k]; /* the target, until the forward pass */
    }
    st = nn_forward(h->nn, ws, x, BATCH, y, err);
    for (int j = 0; st == NBRDF_OK && j < BATCH; j++) {
      float r = dy[j] - y[j]; /* true - head: > 0 is an under-prediction */
      dy[j] = -2.0f * (r > 0.0f ? (float)under : 1.0f) * r / BATCH;
    }
    if (st == NBRDF_OK) st = nn_backward(h->nn, ws, dy, NULL, grad, err);
    if (st == NBRDF_OK) st = nn_adam_step(adam, nn_params(h->nn), grad, err);
  }
  *cpu = bench_cpu_seconds() - c0;
  free(grad), free(perm), nn_workspace_destroy(ws), nn_adam_destroy(adam);
  return st;
}

static void head_free(head *h) {
  nn_workspace_destroy(h->infer), nn_destroy(h->nn);
  memset(h, 0, sizeof *h);
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Near the limit: a clearance is wrong only where the true value is above BAKE_AUDIT_LIMIT,
 * so the margin that matters for the verdict is true - head over those; NEAR widens that set
 * by 0.1 (the clearcoat peaks at 0.907, below it). */
#define NEAR (BAKE_AUDIT_LIMIT - 0.1)

typedef struct under {
  double q[3]; /* true - head: max, p99.9, p99 */
  double near; /* max true - head where true > NEAR (-inf: none) */
  size_t n_near, n_over;
  double bin[R]; /* max true - head per bin of normalised alpha1 */
  size_t worst;  /* index of the max */
  double worst_head;
  size_t wrong; /* true > BAKE_AUDIT_LIMIT yet head + probe <= BAKE_AUDIT_LIMIT */
} under_stat;

static nbrdf_status under_stats(head *h, const set *s, double probe, under_stat *o,
                                nbrdf_error *err) {
  double *e = malloc(s->n * sizeof *e), *pred = malloc(s->n * sizeof *pred);
  if (!e || !pred) return core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
  nbrdf_status st = head_predict(h, s, s->n, NULL, pred, err);
  o->near = -INFINITY, o->n_near = o->n_over = o->wrong = 0, o->worst = 0;
  for (int b = 0; b < R; b++)
    o->bin[b] = -INFINITY;
  for (size_t k = 0; st == NBRDF_OK && k < s->n; k++) {
    e[k] = s->y[k] - pred[k];
    if (e[k] > e[o->worst]) o->worst = k;
    if (s->y[k] > NEAR) o->n_near++, o->near = fmax(o->near, e[k]);
    o->n_over += s->y[k] > BAKE_AUDIT_LIMIT;
    o->wrong += s->y[k] > BAKE_AUDIT_LIMIT && pred[k] + probe <= BAKE_AUDIT_LIMIT;
    int b = (int)(s->u[k * P + NBRDF_BAKE_ALPHA1] * R);
    b = b < 0 ? 0 : b >= R ? R - 1 : b;
    o->bin[b] = fmax(o->bin[b], e[k]);
  }
  if (st == NBRDF_OK) {
    o->worst_head = pred[o->worst];
    qsort(e, s->n, sizeof *e, cmp_double);
    o->q[0] = e[s->n - 1];
    o->q[1] = e[(size_t)floor(0.999 * (double)(s->n - 1))];
    o->q[2] = e[(size_t)floor(0.99 * (double)(s->n - 1))];
  }
  free(e), free(pred);
  return st;
}

/* ------------------------------------------------------------------------- materials -- */

typedef struct material {
  const char *name;
  set s;
  size_t distinct;
  size_t all_measured; /* the audit on every tuple */
  double all_cpu, all_worst;
} material;

static nbrdf_status audit(const ctx *c, const set *s, const size_t *idx, size_t n, size_t *measured,
                          double *cpu, double *worst, nbrdf_error *err) {
  bake_audit a;
  bake_audit_init(&a, n ? n : 1);
  size_t band_worst;
  nbrdf_status st = NBRDF_OK;
  /* In the bake's chunks (bake_band.c's AUDIT_CHUNK, in the order tuples are met): each call
   * has its own rounds, so one call with every tuple would measure more than the bake. */
  for (size_t k = 0; st == NBRDF_OK && k < n; k += AUDIT_CHUNK)
    st = bake_audit_tuples(&a, c->model, s->t, c->lo, c->hi, s->out, idx + k,
                           n - k < AUDIT_CHUNK ? n - k : AUDIT_CHUNK, &band_worst, err);
  *measured = a.measured, *cpu = a.seconds, *worst = a.worst;
  bake_audit_free(&a);
  return st;
}

/* argv[*i] is the material's name; its bake arguments follow up to the next --material. */
static nbrdf_status material_load(ctx *c, int argc, char **argv, int *i, material *m,
                                  nbrdf_error *err) {
  m->name = argv[(*i)++];
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  nbrdf_roughness rough = NBRDF_ROUGHNESS_ALPHA;
  nbrdf_status st = NBRDF_OK;
  for (; st == NBRDF_OK && *i < argc && strcmp(argv[*i], "--material"); (*i)++) {
    const char *a = argv[*i];
    if (!strcmp(a, "--roughness") && *i + 1 < argc) {
      rough = strcmp(argv[++*i], "perceptual") ? NBRDF_ROUGHNESS_ALPHA : NBRDF_ROUGHNESS_PERCEPTUAL;
      continue;
    }
    int id = -1;
    for (int p = 0; p < P; p++) {
      char opt[32];
      snprintf(opt, sizeof opt, "--%s", nbrdf_bake_param_name((nbrdf_bake_param_id)p));
      for (char *q = opt + 2; *q; q++)
        *q = *q == '_' ? '-' : *q;
      if (!strcmp(a, opt)) id = p;
    }
    if (id < 0 || *i + 1 >= argc)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "material %s: unknown argument %s", m->name, a);
    st = nbrdf_bake_param_parse(nbrdf_bake_param_name((nbrdf_bake_param_id)id), argv[++*i],
                                &in.param[id], err);
  }
  texture_param_source *src[P] = {0};
  int w = 0, h = 0, colours = 1;
  if (st == NBRDF_OK) st = bake_open_sources(&in, src, err);
  if (st == NBRDF_OK) st = texture_param_sources_common_size(src, P, &w, &h, err);
  for (int id = 0; st == NBRDF_OK && id < P; id++)
    colours = texture_param_source_channels(src[id]) == 3 ? 3 : colours;
  bake_scene scene = {src, w ? w : 1, h ? h : 1, colours};
  bake_gather_settings gs = {c->lo, c->hi, NULL, rough, NBRDF_RANGE_CLAMP, 0, NULL};
  if (st == NBRDF_OK) st = bake_gather_tuples(&scene, 1, &gs, &m->s.t, &m->s.n, &m->distinct, err);
  for (int id = 0; id < P; id++)
    texture_param_source_free(src[id]);
  if (st == NBRDF_OK) st = complete(c, &m->s, err);
  size_t *idx = st == NBRDF_OK ? malloc(m->s.n * sizeof *idx) : NULL;
  for (size_t k = 0; idx && k < m->s.n; k++)
    idx[k] = k;
  if (st == NBRDF_OK && !idx) st = core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
  if (st == NBRDF_OK)
    st = audit(c, &m->s, idx, m->s.n, &m->all_measured, &m->all_cpu, &m->all_worst, err);
  free(idx);
  return st;
}

/* Share the head clears with margin M, true - head there, the head's CPU-s, and the audit on
 * what it leaves. */
static nbrdf_status material_row(const ctx *c, head *h, const material *m, double M,
                                 nbrdf_error *err) {
  const set *s = &m->s;
  double *pred = malloc(s->n * sizeof *pred);
  size_t *left = malloc(s->n * sizeof *left);
  if (!pred || !left) return core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
  /* The head's cost as a bake would pay it: normalising (params) and one forward pass. */
  double c0 = bench_cpu_seconds();
  for (size_t k = 0; !h->latent && k < s->n; k++)
    for (int id = 0; id < P; id++)
      s->u[k * P + id] = model_material_normalise(c->lo, c->hi, id, s->t[k].p[id]);
  nbrdf_status st = head_predict(h, s, s->n, NULL, pred, err);
  double head_cpu = bench_cpu_seconds() - c0;
  size_t cleared = 0, n_left = 0, missed = 0;
  double worst_e = -INFINITY, worst_cleared = -INFINITY;
  for (size_t k = 0; st == NBRDF_OK && k < s->n; k++) {
    double e = s->y[k] - pred[k];
    worst_e = fmax(worst_e, e);
    if (pred[k] + M <= BAKE_AUDIT_LIMIT) {
      cleared++, worst_cleared = fmax(worst_cleared, s->y[k]);
      missed += e > M;
    } else {
      left[n_left++] = k;
    }
  }
  size_t measured = 0;
  double cpu = 0.0, worst = -1.0;
  if (st == NBRDF_OK) st = audit(c, s, left, n_left, &measured, &cpu, &worst, err);
  if (st == NBRDF_OK)
    printf(
        "  %s, M = %.3f: cleared %zu of %zu (%.1f %%), true - head there up to %.4f (%zu above M), "
        "largest true value cleared %.4f; head %.4f CPU-s; audit of the rest: %zu measured, "
        "%.3f CPU-s (all: %zu, %.3f CPU-s)\n",
        m->name, M, cleared, s->n, 100.0 * (double)cleared / (double)s->n, worst_e, missed,
        worst_cleared, head_cpu, measured, cpu, m->all_measured, m->all_cpu);
  free(pred), free(left);
  return st;
}

/* ------------------------------------------------------------------------------ main -- */

static int parse_list(const char *s, long *v, int cap) {
  int n = 0;
  for (char *end; *s && n < cap; s = *end ? end + 1 : end) {
    v[n++] = strtol(s, &end, 10);
    if (end == s) break;
  }
  return n;
}

int main(int argc, char **argv) {
  const char *bundle = NULL;
  long trains[4] = {4096}, widths[4] = {32};
  int n_train = 1, n_width = 1, inputs = 1; /* bit 0: params, bit 1: latent */
  int steps = 20000, n_draw = 8192;
  double under = 4.0, safety = 1.5, corner_p = 0.2, probe = 0.08;
  unsigned long long seed = 21;
  ctx c = {0};
  c.cache = "/tmp/nbrdf-audit-head";
  int i = 1;
  for (; i < argc && strcmp(argv[i], "--material"); i++) {
    if (!strcmp(argv[i], "--bundle") && i + 1 < argc)
      bundle = argv[++i];
    else if (!strcmp(argv[i], "--train") && i + 1 < argc)
      n_train = parse_list(argv[++i], trains, 4);
    else if (!strcmp(argv[i], "--width") && i + 1 < argc)
      n_width = parse_list(argv[++i], widths, 4);
    else if (!strcmp(argv[i], "--input") && i + 1 < argc) {
      const char *v = argv[++i];
      inputs = (strstr(v, "params") ? 1 : 0) | (strstr(v, "latent") ? 2 : 0);
    } else if (!strcmp(argv[i], "--steps") && i + 1 < argc)
      steps = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--under") && i + 1 < argc)
      under = atof(argv[++i]);
    else if (!strcmp(argv[i], "--safety") && i + 1 < argc)
      safety = atof(argv[++i]);
    else if (!strcmp(argv[i], "--draw") && i + 1 < argc)
      n_draw = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--seed") && i + 1 < argc)
      seed = strtoull(argv[++i], NULL, 10);
    else if (!strcmp(argv[i], "--probe-m") && i + 1 < argc)
      probe = atof(argv[++i]);
    else if (!strcmp(argv[i], "--corner-p") && i + 1 < argc)
      corner_p = atof(argv[++i]);
    else if (!strcmp(argv[i], "--cache") && i + 1 < argc)
      c.cache = argv[++i];
    else {
      fprintf(stderr, "bench_audit_head: unknown argument %s\n", argv[i]);
      return 2;
    }
  }
  nbrdf_error err = {0};
  nbrdf_model *model = NULL;
  if ((bundle ? nbrdf_model_load(bundle, &model, &err)
              : nbrdf_model_load_default(&model, NULL, 0, &err)) != NBRDF_OK)
    return fail(&err);
  c.model = model;
  model_material_ranges(model, c.lo, c.hi);
  c.D = nbrdf_model_latent_dim(model);
  if (c.D > 64) return fprintf(stderr, "bench_audit_head: latent of %d > 64\n", c.D), 1;
  material mat[MAX_MAT];
  int n_mat = 0;
  memset(mat, 0, sizeof mat);
  while (i < argc && n_mat < MAX_MAT) {
    i++; /* --material */
    if (i >= argc) break;
    if (material_load(&c, argc, argv, &i, &mat[n_mat], &err) != NBRDF_OK) return fail(&err);
    double top = 0.0;
    for (size_t k = 0; k < mat[n_mat].s.n; k++)
      top = fmax(top, mat[n_mat].s.y[k]);
    printf("material %s: %zu distinct tuples, every one measured: max %.4f; the audit on all "
           "of them: %zu measured, %.3f CPU-s, worst %.4f\n",
           mat[n_mat].name, mat[n_mat].s.n, top, mat[n_mat].all_measured, mat[n_mat].all_cpu,
           mat[n_mat].all_worst);
    n_mat++;
  }
  set test[N_KIND];
  memset(test, 0, sizeof test);
  for (int k = 0; k < N_KIND; k++) {
    test[k].n = (size_t)n_draw;
    test[k].t = calloc(test[k].n, sizeof *test[k].t);
    draw(&c, k, test[k].n, seed + 1000, corner_p, test[k].t);
    if (complete(&c, &test[k], &err) != NBRDF_OK) return fail(&err);
  }
  printf("held-out draws: %d tuples each, seed %llu; loss weight on under-prediction %g, %d "
         "steps, safety %g; measuring (not cached) %.1f CPU-s so far\n",
         n_draw, seed + 1000, under, steps, safety, c.measure_cpu);
  for (int a = 0; a < n_train; a++) {
    set train = {0};
    if (make_train(&c, (size_t)trains[a], seed, corner_p, &train, &err) != NBRDF_OK)
      return fail(&err);
    for (int b = 0; b < n_width; b++)
      for (int in = 0; in < 2; in++) {
        if (!(inputs >> in & 1)) continue;
        head h = {.latent = in, .I = in ? c.D : P, .W = (int)widths[b]};
        double train_cpu = 0.0, worst = -INFINITY, near = -INFINITY, bin[R];
        under_stat ut, u[N_KIND];
        if (head_train(&h, &train, steps, under, seed, &train_cpu, &err) != NBRDF_OK ||
            under_stats(&h, &train, probe, &ut, &err) != NBRDF_OK)
          return fail(&err);
        for (int r = 0; r < R; r++)
          bin[r] = -INFINITY;
        for (int k = 0; k < N_KIND; k++) {
          if (under_stats(&h, &test[k], probe, &u[k], &err) != NBRDF_OK) return fail(&err);
          worst = fmax(worst, u[k].q[0]);
          near = fmax(near, u[k].near);
          for (int r = 0; r < R; r++)
            bin[r] = fmax(bin[r], u[k].bin[r]);
        }
        const double M = safety * fmax(worst, 0.0);
        printf("N %ld, width %d, input %s (train %.1f CPU-s): true - head, max / p99.9 / p99: "
               "training set %.4f / %.4f / %.4f",
               trains[a], h.W, in ? "latent" : "params", train_cpu, ut.q[0], ut.q[1], ut.q[2]);
        for (int k = 0; k < N_KIND; k++)
          printf("; %s %.4f / %.4f / %.4f", kind_name[k], u[k].q[0], u[k].q[1], u[k].q[2]);
        printf("; M = %g x %.4f = %.4f\n", safety, worst, M);
        for (int k = 0; k < N_KIND; k++) {
          const bake_tuple *t = &test[k].t[u[k].worst];
          printf("  %s: worst at alpha1 %.4g eta %.4g alpha2 %.4g r0 %.4g albedo %.4g sigma_t "
                 "%.4g: true %.4f, head %.4f; true > %.2f: %zu tuples (%zu > %.2f), true - head "
                 "there up to %.4f; with M = %.3f %zu of those would be cleared\n",
                 kind_name[k], (double)t->p[0], (double)t->p[1], (double)t->p[2], (double)t->p[3],
                 (double)t->p[4], (double)t->p[5], test[k].y[u[k].worst], u[k].worst_head, NEAR,
                 u[k].n_near, u[k].n_over, BAKE_AUDIT_LIMIT, u[k].near, probe, u[k].wrong);
        }
        printf("  max true - head by eighth of normalised alpha1 (three draws):");
        for (int r = 0; r < R; r++)
          printf(" %.3f", bin[r]);
        printf("; where true > %.2f: %.4f\n", NEAR, near);
        for (int m = 0; m < n_mat; m++)
          if (material_row(&c, &h, &mat[m], M, &err) != NBRDF_OK ||
              (probe > 0.0 && material_row(&c, &h, &mat[m], probe, &err) != NBRDF_OK))
            return fail(&err);
        head_free(&h);
      }
    set_free(&train);
  }
  printf("measuring (not cached): %.1f CPU-s in all\n", c.measure_cpu);
  for (int k = 0; k < N_KIND; k++)
    set_free(&test[k]);
  for (int m = 0; m < n_mat; m++)
    set_free(&mat[m].s);
  nbrdf_model_destroy(model);
  return 0;
}
