/* The bake's energy audit (bake_audit.h). */
#include "bake/bake_audit.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake/bake_compact.h"
#include "core/error.h"
#include "model/albedo_quad.h"
#include "model/audit_slopes.h"
#include "model/bundle.h"
#include "model/material.h"
#include "model/model_gpu.h"

const double bake_audit_theta_deg[BAKE_AUDIT_N_THETA] = {0.0, 30.0, 60.0, 80.0, 85.0, 89.0};

#define AUDIT_SEED UINT64_C(0x6175646974)

/* Each latent's largest albedo over the audited θi (rho: n rows of BAKE_AUDIT_N_THETA), and
 * where it is. */
static void max_over_theta(const double *rho, size_t n, double *maxv, int *theta_index) {
  for (size_t k = 0; k < n; k++) {
    int best = 0;
    for (int t = 1; t < BAKE_AUDIT_N_THETA; t++)
      if (rho[k * BAKE_AUDIT_N_THETA + t] > rho[k * BAKE_AUDIT_N_THETA + best]) best = t;
    maxv[k] = rho[k * BAKE_AUDIT_N_THETA + best];
    if (theta_index) theta_index[k] = best;
  }
}

static nbrdf_status albedo_max(const nbrdf_model *model, struct gpu_network *gpu, size_t n,
                               const float *latents, const float *sigma, double *maxv,
                               int *theta_index, nbrdf_error *err) {
  if (n == 0) return NBRDF_OK;
  double *rho = malloc(n * BAKE_AUDIT_N_THETA * sizeof *rho);
  if (!rho) return core_fail(err, NBRDF_ERR_MEMORY, "energy audit: out of memory");
  model_runner runner;
  nbrdf_status st =
      gpu ? model_gpu_runner(gpu, 8192, &runner, err)
          : model_runner_create(model->decoder->nn, 4096, NBRDF_NN_INFER, &runner, err);
  if (!st)
    st = model_albedo_decoded(model->decoder, &runner, n, latents, sigma, BAKE_AUDIT_N_THETA,
                              bake_audit_theta_deg, BAKE_AUDIT_SAMPLES, AUDIT_SEED, rho, NULL, err);
  /* The cheap estimate's maximum over θi is noisy and biased upwards (the
   * largest of six noisy values): latents that come near the limit are
   * measured again with BAKE_AUDIT_REFINE_SAMPLES directions. */
  for (size_t k = 0; k < n && !st; k++) {
    double mx = 0.0;
    for (int t = 0; t < BAKE_AUDIT_N_THETA; t++)
      mx = fmax(mx, rho[k * BAKE_AUDIT_N_THETA + t]);
    if (mx > BAKE_AUDIT_REFINE_ABOVE)
      st = model_albedo_decoded(model->decoder, &runner, 1, latents + k * model->latent_dim,
                                sigma ? sigma + k : NULL, BAKE_AUDIT_N_THETA, bake_audit_theta_deg,
                                BAKE_AUDIT_REFINE_SAMPLES, AUDIT_SEED, rho + k * BAKE_AUDIT_N_THETA,
                                NULL, err);
  }
  model_runner_destroy(&runner);
  if (!st) max_over_theta(rho, n, maxv, theta_index);
  free(rho);
  return st;
}

nbrdf_status bake_albedo_max(const nbrdf_model *model, size_t n, const float *latents,
                             const float *sigma, double *maxv, int *theta_index, nbrdf_error *err) {
  return albedo_max(model, NULL, n, latents, sigma, maxv, theta_index, err);
}

static int region(float u) {
  int r = (int)(u * BAKE_AUDIT_REGIONS);
  return r < 0 ? 0 : r >= BAKE_AUDIT_REGIONS ? BAKE_AUDIT_REGIONS - 1 : r;
}

_Static_assert(BAKE_AUDIT_REGIONS == MODEL_AUDIT_REGIONS && BAKE_AUDIT_DIRS == MODEL_AUDIT_DIRS,
               "the bundle's table is the audit's");

static const double *slope_at(const double *slopes, int a, int b, int id) {
  return slopes +
         (((size_t)a * BAKE_AUDIT_REGIONS + (size_t)b) * NBRDF_BAKE_PARAM_COUNT + (size_t)id) *
             BAKE_AUDIT_DIRS;
}

double bake_audit_reach(const double *slopes, const float *u, const float *v) {
  if (!slopes) return INFINITY;
  int au = region(u[NBRDF_BAKE_ALPHA1]), av = region(v[NBRDF_BAKE_ALPHA1]);
  int bu = region(u[NBRDF_BAKE_ALPHA2]), bv = region(v[NBRDF_BAKE_ALPHA2]);
  int a0 = au < av ? au : av, a1 = au < av ? av : au;
  int b0 = bu < bv ? bu : bv, b1 = bu < bv ? bv : bu;
  double d = 0.0;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    double du = (double)u[id] - (double)v[id], s = 0.0;
    if (du == 0.0) continue;
    int dir = du > 0.0 ? 0 : 1;
    for (int a = a0; a <= a1; a++)
      for (int b = b0; b <= b1; b++)
        s = fmax(s, slope_at(slopes, a, b, id)[dir]);
    d += s * fabs(du);
  }
  return d;
}

/* The largest (or with `least`, the smallest) slope of each parameter over the
 * regions and directions; without slopes, infinite (or 0). */
static void slope_extreme(const double *slopes, int least, double *slope) {
  enum { N = BAKE_AUDIT_REGIONS * BAKE_AUDIT_REGIONS };
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    slope[id] = (least != 0) == (slopes != NULL) ? INFINITY : 0.0;
    for (int k = 0; slopes && k < N; k++)
      for (int dir = 0; dir < BAKE_AUDIT_DIRS; dir++) {
        double x =
            slopes[((size_t)k * NBRDF_BAKE_PARAM_COUNT + (size_t)id) * BAKE_AUDIT_DIRS + dir];
        slope[id] = least ? fmin(slope[id], x) : fmax(slope[id], x);
      }
  }
}

void bake_audit_slope_max(const double *slopes, double *slope) { slope_extreme(slopes, 0, slope); }

/* The polar rule's maximum over θi of n latents through `runner`, destroyed here; st: whether
 * creating it failed. */
static nbrdf_status precise_run(const model_decoder *dec, model_runner *runner, nbrdf_status st,
                                size_t n, const float *latents, double *maxv, int *theta_index,
                                nbrdf_error *err) {
  if (st) return st; /* the runner was not created */
  double *rho = malloc(n * BAKE_AUDIT_N_THETA * sizeof *rho);
  if (!rho) st = core_fail(err, NBRDF_ERR_MEMORY, "energy audit: out of memory");
  if (!st)
    st = model_albedo_decoded_polar(dec, runner, n, latents, BAKE_AUDIT_N_THETA,
                                    bake_audit_theta_deg, BAKE_AUDIT_POLAR_RINGS,
                                    BAKE_AUDIT_POLAR_PHI, rho, err);
  model_runner_destroy(runner);
  if (!st) max_over_theta(rho, n, maxv, theta_index);
  free(rho);
  return st;
}

nbrdf_status bake_albedo_precise_with(const model_decoder *dec, size_t n, const float *latents,
                                      double *maxv, int *theta_index, nbrdf_error *err) {
  if (n == 0) return NBRDF_OK;
  model_runner runner;
  nbrdf_status st = model_runner_create(dec->nn, 4096, NBRDF_NN_INFER, &runner, err);
  return precise_run(dec, &runner, st, n, latents, maxv, theta_index, err);
}

nbrdf_status bake_albedo_precise(const nbrdf_model *model, struct gpu_network *gpu, size_t n,
                                 const float *latents, const float *sigma, double *maxv,
                                 int *theta_index, nbrdf_error *err) {
  if (n == 0) return NBRDF_OK;
  model_runner runner;
  nbrdf_status st =
      gpu ? model_gpu_runner(gpu, 8192, &runner, err)
          : model_runner_create(model->decoder->nn, 4096, NBRDF_NN_INFER, &runner, err);
  /* The polar rule does not need the proxy: its rings cover every lobe width. */
  (void)sigma;
  return precise_run(model->decoder, &runner, st, n, latents, maxv, theta_index, err);
}

struct bake_audit_cell {
  uint64_t key; /* 0: empty */
  size_t head;  /* its first anchor (index into anchors), NO_ANCHOR: none */
};

/* A measured tuple: its normalised parameters and maximum albedo. */
struct bake_audit_anchor {
  float u[NBRDF_BAKE_PARAM_COUNT];
  unsigned char q[NBRDF_BAKE_PARAM_COUNT]; /* its cell */
  double value;
  size_t next; /* the next anchor of its cell */
};

#define NO_ANCHOR ((size_t)-1)
/* Rounds of measurement per call before every tuple still uncleared is measured. */
#define AUDIT_ROUNDS 4
/* A tuple with no anchor near it is expected to measure this much when the
 * round's picks are spread (only the spread depends on it, never a verdict). */
#define AUDIT_GUESS 0.8

void bake_audit_init(bake_audit *a, size_t cap) {
  memset(a, 0, sizeof *a);
  a->cap = cap;
  a->worst = -1.0;
}

void bake_audit_free(bake_audit *a) {
  free(a->lat), free(a->sigma), free(a->u), free(a->maxv), free(a->theta), free(a->guess);
  free(a->upper), free(a->rho), free(a->rest);
  free(a->pick), free(a->pending), free(a->q), free(a->cells), free(a->anchors);
  size_t cap = a->cap;
  struct gpu_network *gpu = a->gpu_decoder;
  memset(a, 0, sizeof *a);
  a->cap = cap;
  a->gpu_decoder = gpu;
}

static uint64_t mix64(uint64_t x) {
  x ^= x >> 33, x *= UINT64_C(0xff51afd7ed558ccd);
  x ^= x >> 33, x *= UINT64_C(0xc4ceb9fe1a85ec53);
  return x ^ (x >> 33);
}

static uint64_t cell_key(const unsigned char *q) {
  uint64_t key = 1;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    key = key * (BAKE_AUDIT_GRID + 1) + q[id];
  return key;
}

/* The cell of key, or the empty slot where it goes (cells_cap a power of two,
 * at most half full). */
static size_t cell_slot(const bake_audit *a, uint64_t key) {
  size_t mask = a->cells_cap - 1, s = (size_t)mix64(key) & mask;
  while (a->cells[s].key && a->cells[s].key != key)
    s = (s + 1) & mask;
  return s;
}

static int cells_room(bake_audit *a, size_t more) {
  if (2 * (a->cells_used + more) <= a->cells_cap) return 1;
  size_t cap = a->cells_cap ? a->cells_cap : 256;
  while (2 * (a->cells_used + more) > cap)
    cap *= 2;
  bake_audit_cell *old = a->cells;
  size_t old_cap = a->cells_cap;
  a->cells = calloc(cap, sizeof *a->cells);
  if (!a->cells) {
    a->cells = old;
    return 0;
  }
  a->cells_cap = cap;
  for (size_t i = 0; i < old_cap; i++)
    if (old[i].key) a->cells[cell_slot(a, old[i].key)] = old[i];
  free(old);
  return 1;
}

static int anchors_room(bake_audit *a, size_t more) {
  if (a->n_anchors + more <= a->anchors_cap) return 1;
  size_t cap = a->anchors_cap ? 2 * a->anchors_cap : 256;
  while (cap < a->n_anchors + more)
    cap *= 2;
  bake_audit_anchor *p = realloc(a->anchors, cap * sizeof *p);
  if (!p) return 0;
  a->anchors = p, a->anchors_cap = cap;
  return 1;
}

static int scratch_room(bake_audit *a, size_t n, size_t D) {
  if (n <= a->scratch_cap) return 1;
  free(a->lat), free(a->sigma), free(a->u), free(a->maxv), free(a->theta), free(a->guess);
  free(a->upper), free(a->rho), free(a->rest);
  free(a->pick), free(a->pending), free(a->q);
  a->upper = malloc(n * sizeof *a->upper);
  a->rho = malloc(n * BAKE_AUDIT_N_THETA * sizeof *a->rho);
  a->rest = malloc(n * sizeof *a->rest);
  a->lat = malloc(n * D * sizeof *a->lat);
  a->sigma = malloc(n * sizeof *a->sigma);
  a->u = malloc(n * NBRDF_BAKE_PARAM_COUNT * sizeof *a->u);
  a->maxv = malloc(n * sizeof *a->maxv);
  a->theta = malloc(n * sizeof *a->theta);
  a->guess = malloc(n * sizeof *a->guess);
  a->pick = malloc(n * sizeof *a->pick);
  a->pending = malloc(n * sizeof *a->pending);
  a->q = malloc(n * NBRDF_BAKE_PARAM_COUNT * sizeof *a->q);
  a->scratch_cap = n;
  if (a->lat && a->sigma && a->u && a->maxv && a->theta && a->guess && a->pick && a->pending &&
      a->q && a->upper && a->rho && a->rest)
    return 1;
  a->scratch_cap = 0;
  return 0;
}

/* The polar rule at the angles of mask (bits into bake_audit_theta_deg) for
 * the n latents lat [n × D]: rho[k · BAKE_AUDIT_N_THETA + angle] of those angles. */
static nbrdf_status polar_at(const nbrdf_model *model, struct gpu_network *gpu, size_t n,
                             const float *lat, int mask, double *rho, nbrdf_error *err) {
  double deg[BAKE_AUDIT_N_THETA];
  int at[BAKE_AUDIT_N_THETA], nt = 0;
  for (int t = 0; t < BAKE_AUDIT_N_THETA; t++)
    if (mask >> t & 1) deg[nt] = bake_audit_theta_deg[t], at[nt++] = t;
  double *r = malloc(n * (size_t)nt * sizeof *r);
  if (!r) return core_fail(err, NBRDF_ERR_MEMORY, "energy audit: out of memory");
  model_runner runner;
  nbrdf_status st =
      gpu ? model_gpu_runner(gpu, 8192, &runner, err)
          : model_runner_create(model->decoder->nn, 4096, NBRDF_NN_INFER, &runner, err);
  if (!st) {
    st = model_albedo_decoded_polar(model->decoder, &runner, n, lat, nt, deg,
                                    BAKE_AUDIT_POLAR_RINGS, BAKE_AUDIT_POLAR_PHI, r, err);
    model_runner_destroy(&runner);
  }
  for (size_t k = 0; k < n && !st; k++)
    for (int j = 0; j < nt; j++)
      rho[k * BAKE_AUDIT_N_THETA + at[j]] = r[k * (size_t)nt + (size_t)j];
  free(r);
  return st;
}

/* The largest of rho's angles in mask, and where (index into bake_audit_theta_deg);
 * NaN when one is NaN (as an anchor it then clears nothing: every bound compares false). */
static double max_at(const double *rho, int mask, int *theta) {
  double m = -INFINITY;
  *theta = 0;
  for (int t = 0; t < BAKE_AUDIT_N_THETA; t++) {
    if (!(mask >> t & 1)) continue;
    if (isnan(rho[t])) return NAN;
    if (rho[t] > m) m = rho[t], *theta = t;
  }
  return m;
}

/* Measures the m tuples idx[pick[j]] into maxv[j], theta[j] (the measured
 * maximum) and upper[j] (the anchor's value): first at the screen's angles, then
 * at the others (those tuples in one batch) where the screen's values do not
 * rise towards grazing or its maximum plus BAKE_AUDIT_THETA_GAP is above the
 * limit. */
static nbrdf_status measure(bake_audit *a, const nbrdf_model *model, const float *out,
                            const size_t *idx, size_t m, nbrdf_error *err) {
  enum { ALL = (1 << BAKE_AUDIT_N_THETA) - 1 };
  _Static_assert(BAKE_AUDIT_SCREEN_MASK == 0x31, "the rising test reads angles 0, 4 and 5");
  const size_t D = (size_t)nbrdf_model_latent_dim(model);
  const size_t stored = a->compact ? (size_t)a->compact->work_dim : D;
  for (size_t j = 0; j < m; j++) {
    const float *o = out + idx[a->pick[j]] * (stored + 2);
    if (a->compact)
      bake_compact_reduce(a->compact, o, a->lat + j * D);
    else
      memcpy(a->lat + j * D, o, D * sizeof *a->lat);
    a->sigma[j] = o[stored];
  }
  a->measured += m;
  nbrdf_status st = polar_at(model, a->gpu_decoder, m, a->lat, BAKE_AUDIT_SCREEN_MASK, a->rho, err);
  size_t nr = 0;
  for (size_t j = 0; j < m && !st; j++) {
    a->maxv[j] = max_at(a->rho + j * BAKE_AUDIT_N_THETA, BAKE_AUDIT_SCREEN_MASK, &a->theta[j]);
    const double *rho = a->rho + j * BAKE_AUDIT_N_THETA;
    /* rising towards grazing over the screen's angles (0, 85, 89 deg) */
    int rising = rho[0] <= rho[4] && rho[4] <= rho[5];
    a->upper[j] = a->maxv[j] + BAKE_AUDIT_THETA_GAP;
    if (!rising || a->upper[j] > BAKE_AUDIT_LIMIT) {
      /* compact the latents to finish at the front of lat (j >= nr) */
      memmove(a->lat + nr * D, a->lat + j * D, D * sizeof *a->lat);
      a->rest[nr++] = j;
    }
  }
  if (st || !nr) return st;
  a->finished += nr;
  double *r = malloc(nr * BAKE_AUDIT_N_THETA * sizeof *r);
  if (!r) return core_fail(err, NBRDF_ERR_MEMORY, "energy audit: out of memory");
  st = polar_at(model, a->gpu_decoder, nr, a->lat, ALL & ~BAKE_AUDIT_SCREEN_MASK, r, err);
  for (size_t i = 0; i < nr && !st; i++) {
    size_t j = a->rest[i];
    double *rho = a->rho + j * BAKE_AUDIT_N_THETA;
    for (int t = 0; t < BAKE_AUDIT_N_THETA; t++)
      if (!(BAKE_AUDIT_SCREEN_MASK >> t & 1)) rho[t] = r[i * BAKE_AUDIT_N_THETA + (size_t)t];
    a->maxv[j] = a->upper[j] = max_at(rho, ALL, &a->theta[j]);
  }
  free(r);
  return st;
}

/* Records measured tuple j (tuple index k) in the counts and the worst. */
static void tally(bake_audit *a, size_t j, size_t k, size_t *band_worst) {
  a->over += a->maxv[j] > BAKE_AUDIT_LIMIT;
  if (a->maxv[j] > a->worst) {
    a->worst = a->maxv[j], a->worst_theta = a->theta[j];
    *band_worst = k;
  }
}

/* Whether cells q and r are the same or next to each other along one parameter. */
static int next_cell(const unsigned char *q, const unsigned char *r) {
  int steps = 0;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    steps += abs((int)q[id] - (int)r[id]);
  return steps <= 1;
}

static void cell_of(const float *u, unsigned char *q) {
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    int g = (int)(u[id] * BAKE_AUDIT_GRID);
    q[id] = (unsigned char)(g < 0 ? 0 : g >= BAKE_AUDIT_GRID ? BAKE_AUDIT_GRID - 1 : g);
  }
}

/* The smallest bound anchor + noise + reach over the anchors (stops at the first
 * that clears the limit): those of the tuple's cell and of the cells next to it
 * along one parameter first, then the others, newest first (the bake meets
 * tuples in texel order, so its recent anchors are the likely near ones), each
 * skipped when even the smallest slopes (smin) cannot clear it; *near: the
 * value of the anchor that gave it (NAN: none). */
static double bound(const bake_audit *a, const double *slopes, const double *smin, const float *u,
                    const unsigned char *q, double *near) {
  enum { P = NBRDF_BAKE_PARAM_COUNT };
  double best = INFINITY;
  *near = NAN;
  for (int nb = 0; nb <= 2 * P; nb++) {
    unsigned char qn[P];
    memcpy(qn, q, sizeof qn);
    if (nb) {
      int id = (nb - 1) / 2, step = (nb - 1) % 2 ? 1 : -1;
      if ((step < 0 && q[id] == 0) || (step > 0 && q[id] + 1 >= BAKE_AUDIT_GRID)) continue;
      qn[id] = (unsigned char)(q[id] + step);
    }
    const bake_audit_cell *c = &a->cells[cell_slot(a, cell_key(qn))];
    if (!c->key) continue;
    for (size_t i = c->head; i != NO_ANCHOR; i = a->anchors[i].next) {
      double b =
          a->anchors[i].value + BAKE_AUDIT_NOISE + bake_audit_reach(slopes, u, a->anchors[i].u);
      if (b < best) best = b, *near = a->anchors[i].value;
      if (best <= BAKE_AUDIT_LIMIT) return best;
    }
  }
  for (size_t i = a->n_anchors; i-- > 0;) {
    const bake_audit_anchor *an = &a->anchors[i];
    double lb = an->value + BAKE_AUDIT_NOISE;
    for (int id = 0; id < P; id++)
      lb += smin[id] * fabs((double)u[id] - (double)an->u[id]);
    if (!(lb < best) || lb > BAKE_AUDIT_LIMIT || next_cell(q, an->q)) continue; /* or tried above */
    double b = an->value + BAKE_AUDIT_NOISE + bake_audit_reach(slopes, u, an->u);
    if (b < best) best = b, *near = an->value;
    if (best <= BAKE_AUDIT_LIMIT) return best;
  }
  return best;
}

/* Files a measured tuple (its u, q and value) as an anchor of its cell. */
static void add_anchor(bake_audit *a, const float *u, const unsigned char *q, double value) {
  size_t s = cell_slot(a, cell_key(q));
  if (!a->cells[s].key) {
    a->cells[s].key = cell_key(q);
    a->cells[s].head = NO_ANCHOR;
    a->cells_used++;
  }
  bake_audit_anchor *an = &a->anchors[a->n_anchors];
  memcpy(an->u, u, sizeof an->u);
  memcpy(an->q, q, sizeof an->q);
  an->value = value;
  an->next = a->cells[s].head;
  a->cells[s].head = a->n_anchors++;
}

static double cpu_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct audit_order {
  double key;
  size_t k;
} audit_order;

/* Σ_i (up slope_i - down slope_i) u_i in the tuple's region: large where an anchor
 * clears much below it (0 without slopes). */
static double pick_key(const double *slopes, const float *u) {
  if (!slopes) return 0.0;
  double key = 0.0;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    const double *s =
        slope_at(slopes, region(u[NBRDF_BAKE_ALPHA1]), region(u[NBRDF_BAKE_ALPHA2]), id);
    key += (s[0] - s[1]) * (double)u[id];
  }
  return key;
}

/* Descending key; ties in bake order, so the order is the same on every machine. */
static int by_key(const void *x, const void *y) {
  const audit_order *p = x, *q = y;
  if (p->key != q->key) return p->key > q->key ? -1 : 1;
  return (p->k > q->k) - (p->k < q->k);
}

static nbrdf_status audit_tuples(bake_audit *a, const nbrdf_model *model, const bake_tuple *t,
                                 const float *lo, const float *hi, const float *out,
                                 const size_t *idx, size_t n, size_t *band_worst, nbrdf_error *err);

nbrdf_status bake_audit_tuples(bake_audit *a, const nbrdf_model *model, const bake_tuple *t,
                               const float *lo, const float *hi, const float *out,
                               const size_t *idx, size_t n, size_t *band_worst, nbrdf_error *err) {
  double c0 = cpu_seconds();
  nbrdf_status st = audit_tuples(a, model, t, lo, hi, out, idx, n, band_worst, err);
  a->seconds += cpu_seconds() - c0;
  return st;
}

static nbrdf_status audit_tuples(bake_audit *a, const nbrdf_model *model, const bake_tuple *t,
                                 const float *lo, const float *hi, const float *out,
                                 const size_t *idx, size_t n, size_t *band_worst,
                                 nbrdf_error *err) {
  enum { P = NBRDF_BAKE_PARAM_COUNT };
  *band_worst = (size_t)-1;
  size_t room = a->cap > a->audited ? a->cap - a->audited : 0;
  if (n > room) a->skipped += n - room, n = room;
  if (n == 0) return NBRDF_OK;
  const size_t D = (size_t)nbrdf_model_latent_dim(model);
  /* Measured for the bundle's weights, or none: then no tuple is cleared by another. */
  const double *slopes = model_audit_slopes(model);
  if (!scratch_room(a, n, D) || !cells_room(a, n) || !anchors_room(a, n))
    return core_fail(err, NBRDF_ERR_MEMORY, "energy audit: out of memory");
  double smin[P];
  slope_extreme(slopes, 1, smin);
  audit_order *order = malloc(n * sizeof *order);
  if (!order) return core_fail(err, NBRDF_ERR_MEMORY, "energy audit: out of memory");
  for (size_t k = 0; k < n; k++) {
    float *u = a->u + k * P;
    for (int id = 0; id < P; id++)
      u[id] = model_material_normalise(lo, hi, id, t[idx[k]].p[id]);
    cell_of(u, a->q + k * P);
    order[k] = (audit_order){pick_key(slopes, u), k};
  }
  /* Picks are made in this order: a tuple high where the albedo rises faster than it
   * falls clears more below it than one low clears above it. */
  qsort(order, n, sizeof *order, by_key);
  for (size_t k = 0; k < n; k++)
    a->pending[k] = order[k].k;
  free(order);
  /* Rounds: a tuple some anchor's bound clears is done; of the others, a spread
   * set is measured (a pick stands for the pending tuples it is expected to
   * clear), and the rest wait for the next round; the last round measures all
   * that are left. A tuple above the limit is never cleared, so it is always
   * measured itself. */
  size_t np = n;
  for (int round = 0; np; round++) {
    size_t keep = 0;
    for (size_t i = 0; i < np; i++) {
      size_t k = a->pending[i];
      if (!slopes ||
          !(bound(a, slopes, smin, a->u + k * P, a->q + k * P, &a->guess[k]) <= BAKE_AUDIT_LIMIT))
        a->pending[keep++] = k;
    }
    np = keep;
    size_t m = 0;
    keep = 0;
    for (size_t i = 0; i < np; i++) {
      size_t k = a->pending[i];
      int covered = 0;
      /* without slopes nothing clears anything: every tuple is a pick of the first round */
      for (size_t j = 0; slopes && round < AUDIT_ROUNDS - 1 && j < m && !covered; j++) {
        size_t pj = a->pick[j];
        double g = isnan(a->guess[pj]) ? AUDIT_GUESS : a->guess[pj];
        covered = g + BAKE_AUDIT_NOISE + bake_audit_reach(slopes, a->u + k * P, a->u + pj * P) <=
                  BAKE_AUDIT_LIMIT;
      }
      if (covered)
        a->pending[keep++] = k;
      else
        a->pick[m++] = k;
    }
    np = keep;
    nbrdf_status st = measure(a, model, out, idx, m, err);
    if (st) return st;
    for (size_t j = 0; j < m; j++) {
      size_t k = a->pick[j];
      add_anchor(a, a->u + k * P, a->q + k * P, a->upper[j]);
      tally(a, j, idx[k], band_worst);
    }
  }
  a->audited += n;
  return NBRDF_OK;
}

void bake_audit_found(bake_audit *a, const bake_tuple *t, int x, int y, int c) {
  a->tuple = *t, a->x = x, a->y = y, a->c = c;
}

void bake_audit_message(const bake_audit *a, int rgb, char *buf, size_t cap) {
  buf[0] = '\0';
  size_t len = 0;
  if (a->audited && a->worst > BAKE_AUDIT_LIMIT) {
    const float *p = a->tuple.p;
    char chan[16] = "";
    if (rgb) snprintf(chan, sizeof chan, " channel %c", "RGB"[a->c % 3]);
    int n = snprintf(buf, cap,
                     "energy audit: %zu of %zu distinct latents decode to a directional albedo "
                     "above %.2f (the model creates energy there); the worst, %.3f at theta_i = "
                     "%g deg, at texel (%d, %d)%s: alpha1=%g eta=%g alpha2=%g r0=%g albedo=%g "
                     "sigma_t=%g",
                     a->over, a->audited, BAKE_AUDIT_LIMIT, a->worst,
                     bake_audit_theta_deg[a->worst_theta], a->x, a->y, chan,
                     (double)p[NBRDF_BAKE_ALPHA1], (double)p[NBRDF_BAKE_ETA],
                     (double)p[NBRDF_BAKE_ALPHA2], (double)p[NBRDF_BAKE_R0],
                     (double)p[NBRDF_BAKE_ALBEDO], (double)p[NBRDF_BAKE_SIGMA_T]);
    len = n > 0 && (size_t)n < cap ? (size_t)n : len;
  }
  if (a->skipped && len < cap)
    snprintf(buf + len, cap - len,
             "%senergy audit: %zu distinct latents past the first %zu were "
             "not audited (nbrdf:maxAlbedo covers those audited)",
             len ? "; " : "", a->skipped, a->audited);
}
