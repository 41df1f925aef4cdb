/* The energy audit's slopes of a bundle (bake_audit_slopes.h). */
#include "bake/bake_audit_slopes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/rng.h"
#include "model/material.h"

enum {
  P = NBRDF_BAKE_PARAM_COUNT,
  R = BAKE_AUDIT_REGIONS,
  DIRS = BAKE_AUDIT_DIRS,
  N_STEP = BAKE_AUDIT_SLOPES_STEPS
};
static const double step_of[N_STEP] = {1.0 / 32, 1.0 / 16, 1.0 / 8, 1.0 / 4};
/* Bases measured per call of the decoder's batch (progress and cancel between). */
#define CHUNK 64

static int region(double u) {
  int r = (int)(u * R);
  return r < 0 ? 0 : r >= R ? R - 1 : r;
}

/* The `per` tuples of base b (normalised, into ub) drawn from rng. */
static void draw_base(core_rng *rng, int sharp, size_t b, const float *lo, const float *hi, int per,
                      double *ub) {
  for (int id = 0; id < P; id++)
    ub[id] = core_rng_uniform(rng);
  /* stratified over the slope regions of (alpha1, alpha2) */
  ub[NBRDF_BAKE_ALPHA1] = ((double)(b % R) + ub[NBRDF_BAKE_ALPHA1]) / R;
  ub[NBRDF_BAKE_ALPHA2] = ((double)(b / R % R) + ub[NBRDF_BAKE_ALPHA2]) / R;
  if (sharp) { /* the clearcoat of issue 33 (bench/audit_cost.sh) */
    ub[NBRDF_BAKE_ALPHA1] = 0.0;
    ub[NBRDF_BAKE_ETA] = model_material_normalise(lo, hi, NBRDF_BAKE_ETA, 1.45f);
    ub[NBRDF_BAKE_ALBEDO] = model_material_normalise(lo, hi, NBRDF_BAKE_ALBEDO, 0.8f);
    ub[NBRDF_BAKE_SIGMA_T] = model_material_normalise(lo, hi, NBRDF_BAKE_SIGMA_T, 1.0f);
    ub[NBRDF_BAKE_R0] = 0.5 + 0.5 * ub[NBRDF_BAKE_R0];
  }
  const double cell = 1.0 / BAKE_AUDIT_GRID;
  for (int s = 1; s < per; s++) {
    double *us = ub + (size_t)s * P;
    memcpy(us, ub, P * sizeof *us);
    if (s <= N_STEP * P) { /* a step along one parameter, inward */
      int id = (s - 1) / N_STEP;
      double h = step_of[(s - 1) % N_STEP];
      us[id] += us[id] + h <= 1.0 ? h : -h;
    } else { /* a member of the base's cell */
      for (int id = 0; id < P; id++) {
        if (sharp && id != NBRDF_BAKE_ALPHA2 && id != NBRDF_BAKE_R0) continue;
        int q = (int)(ub[id] * BAKE_AUDIT_GRID);
        q = q >= BAKE_AUDIT_GRID ? BAKE_AUDIT_GRID - 1 : q;
        us[id] = (q + core_rng_uniform(rng)) * cell;
      }
    }
  }
}

void bake_audit_slopes_draws_free(bake_audit_slopes_draws *d) {
  if (!d) return;
  free(d->t), free(d->u), free(d->value), free(d->lat), free(d->sigma);
  memset(d, 0, sizeof *d);
}

nbrdf_status bake_audit_slopes_measure(const nbrdf_model *model, const bake_audit_slopes_options *o,
                                       double *table, bake_audit_slopes_draws *keep,
                                       nbrdf_error *err) {
  if (!model || !o || !table || o->bases < 0 || o->sharp_bases < 0 ||
      o->bases + o->sharp_bases < 1 || o->bases > (1 << 20) || o->sharp_bases > (1 << 20))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "audit slopes: bases %d and clearcoat bases %d (expected 0..1048576, at "
                     "least one in all)",
                     o ? o->bases : 0, o ? o->sharp_bases : 0);
  float lo[P], hi[P];
  model_material_ranges(model, lo, hi);
  const size_t D = (size_t)nbrdf_model_latent_dim(model);
  const int per = N_STEP * P + 2;
  const size_t nb = (size_t)o->bases + (size_t)o->sharp_bases, n = nb * (size_t)per;
  bake_audit_slopes_draws d = {.n_bases = nb, .n_sharp = (size_t)o->sharp_bases, .per = per};
  d.t = calloc(n, sizeof *d.t);
  d.u = malloc(n * P * sizeof *d.u);
  d.value = malloc(n * sizeof *d.value);
  d.lat = malloc(n * D * sizeof *d.lat);
  d.sigma = malloc(n * sizeof *d.sigma);
  float *out = malloc((size_t)CHUNK * per * (D + 2) * sizeof *out);
  nbrdf_status st = NBRDF_OK;
  if (!d.t || !d.u || !d.value || !d.lat || !d.sigma || !out)
    st = core_fail(err, NBRDF_ERR_MEMORY, "audit slopes: out of memory for %zu tuples", n);
  /* Two independent streams, so the whole-range draw is the same with or without
   * the clearcoat's. */
  core_rng whole, sharp;
  core_rng_init(&whole, o->seed, 0);
  core_rng_init(&sharp, o->seed, 1);
  for (size_t b = 0; b < nb && !st; b++) {
    int is_sharp = b >= (size_t)o->bases;
    double *ub = d.u + b * per * P;
    draw_base(is_sharp ? &sharp : &whole, is_sharp, is_sharp ? b - (size_t)o->bases : b, lo, hi,
              per, ub);
    /* what the audit sees: the parameters as a bake would give them */
    for (size_t k = b * per; k < (b + 1) * per; k++)
      for (int id = 0; id < P; id++) {
        d.t[k].p[id] = model_material_unnormalise(lo, hi, id, d.u[k * P + id]);
        d.u[k * P + id] = model_material_normalise(lo, hi, id, d.t[k].p[id]);
      }
  }
  for (size_t b0 = 0; b0 < nb && !st; b0 += CHUNK) {
    if (o->progress && o->progress(o->user, "audit slopes", (double)b0, (double)nb)) {
      st =
          core_fail(err, NBRDF_ERR_CANCELLED, "audit slopes: cancelled at base %zu of %zu", b0, nb);
      break;
    }
    size_t m = (nb - b0 < CHUNK ? nb - b0 : CHUNK) * per, k0 = b0 * per;
    st = bake_tuples_evaluate(model, d.t + k0, NULL, m, out, err);
    for (size_t k = 0; k < m && !st; k++) {
      memcpy(d.lat + (k0 + k) * D, out + k * (D + 2), D * sizeof *d.lat);
      d.sigma[k0 + k] = out[k * (D + 2) + D];
    }
    if (!st)
      st = bake_albedo_precise(model, NULL, m, d.lat + k0 * D, d.sigma + k0, d.value + k0, NULL,
                               err);
  }
  free(out);
  for (size_t k = 0; k < n && !st; k++)
    if (!isfinite(d.value[k]))
      st = core_fail(err, NBRDF_ERR_ARGUMENT,
                     "audit slopes: the decoded albedo of alpha1=%g eta=%g alpha2=%g r0=%g "
                     "albedo=%g sigma_t=%g is %g: the bundle's networks are not usable",
                     (double)d.t[k].p[0], (double)d.t[k].p[1], (double)d.t[k].p[2],
                     (double)d.t[k].p[3], (double)d.t[k].p[4], (double)d.t[k].p[5], d.value[k]);
  if (!st && o->progress) o->progress(o->user, "audit slopes", (double)nb, (double)nb);
  if (st) {
    bake_audit_slopes_draws_free(&d);
    return st;
  }
  /* The bound's model: m(u) - m(a) <= NOISE + Σ slope |u - a|, the slope of the
   * direction from a to u (m: the audit's measurement, whose error is part of
   * NOISE). A step between a base and a tuple is a rise one way and a fall the
   * other, so it gives a need to both directions. */
  static const double zero[R][R][P][DIRS];
  double(*reg)[R][P][DIRS] = malloc(sizeof zero);
  double top[P][DIRS] = {{0}};
  int seen[R][R] = {{0}};
  if (!reg) {
    bake_audit_slopes_draws_free(&d);
    return core_fail(err, NBRDF_ERR_MEMORY, "audit slopes: out of memory");
  }
  memcpy(reg, zero, sizeof zero);
  /* Every step counts, the clearcoat's along all six parameters too: one-sided slopes
   * need them (in that family a lower medium albedo raises the decoded albedo, which
   * the whole range's draws hardly see). */
  for (size_t b = 0; b < nb; b++) {
    size_t k = b * per;
    for (int id = 0; id < P; id++) {
      for (int j = 0; j < N_STEP; j++) {
        size_t s = k + 1 + (size_t)id * N_STEP + (size_t)j;
        double du = d.u[s * P + id] - d.u[k * P + id];
        double dm = d.value[s] - d.value[k];
        if (du == 0.0) continue;
        double need = (fabs(dm) - BAKE_AUDIT_NOISE) / fabs(du);
        if (need > d.need[id]) d.need[id] = need, d.need_at[id] = k, d.need_step[id] = s;
        /* from the base to the step (direction of du) it rises by dm; back, by -dm */
        double want[DIRS];
        want[du > 0.0 ? 0 : 1] = (dm - BAKE_AUDIT_NOISE) / fabs(du);
        want[du > 0.0 ? 1 : 0] = (-dm - BAKE_AUDIT_NOISE) / fabs(du);
        /* every region the step spans needs it (bake_audit_reach takes the largest) */
        int a0 = region(d.u[k * P + NBRDF_BAKE_ALPHA1]),
            a1 = region(d.u[s * P + NBRDF_BAKE_ALPHA1]);
        int c0 = region(d.u[k * P + NBRDF_BAKE_ALPHA2]),
            c1 = region(d.u[s * P + NBRDF_BAKE_ALPHA2]);
        for (int dir = 0; dir < DIRS; dir++) {
          top[id][dir] = fmax(top[id][dir], want[dir]);
          for (int a = a0 < a1 ? a0 : a1; a <= (a0 < a1 ? a1 : a0); a++)
            for (int c = c0 < c1 ? c0 : c1; c <= (c0 < c1 ? c1 : c0); c++)
              reg[a][c][id][dir] = fmax(reg[a][c][id][dir], want[dir]), seen[a][c] = 1;
        }
      }
    }
  }
  for (int a = 0; a < R; a++)
    for (int c = 0; c < R; c++)
      for (int id = 0; id < P; id++)
        for (int dir = 0; dir < DIRS; dir++) {
          double v = seen[a][c] ? fmax(reg[a][c][id][dir], top[id][dir] / 3.0) : top[id][dir];
          table[(((size_t)a * R + c) * P + id) * DIRS + dir] = fmax(0.25, ceil(150.0 * v) / 100.0);
        }
  free(reg);
  if (keep)
    *keep = d;
  else
    bake_audit_slopes_draws_free(&d);
  return NBRDF_OK;
}
