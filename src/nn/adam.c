/* Adam (Kingma & Ba 2015, Algorithm 1) with decoupled weight decay (AdamW) and the paper's step
 * decay of the learning rate, over any float array. Parameter groups are runs of indices with
 * their own base learning rate and weight decay. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "nn/internal.h"

/* The layering network steps ~1.1 M parameters per batch of a few dozen pairs, so this loop
 * was a fifth of its training time while it stayed scalar (NN_HOT, nn/internal.h, says what
 * vectorises it). */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("O3")
#endif

#define MAX_GROUPS 65535

typedef struct adam_group {
  float lr, weight_decay;
} adam_group;

struct nn_adam {
  nn_adam_options opts;
  size_t n;
  float *m, *v;
  uint16_t *group_of; /* NULL until the first group is added: everything in group 0 */
  adam_group *groups;
  int n_groups; /* including group 0, the default */
  int64_t t;
};

static nbrdf_status check_options(const nn_adam_options *o, nbrdf_error *err) {
  nbrdf_status st;
  if ((st = core_check_range(err, "adam lr", o->lr, 0.0, 1e6)) ||
      (st = core_check_range(err, "adam beta1", o->beta1, 0.0, 0.999999)) ||
      (st = core_check_range(err, "adam beta2", o->beta2, 0.0, 0.999999999)) ||
      (st = core_check_range(err, "adam eps", o->eps, 0.0, 1.0)) ||
      (st = core_check_range(err, "adam weight_decay", o->weight_decay, 0.0, 1e6)) ||
      (st = core_check_range(err, "adam decay_every", o->decay_every, 0.0, 2e9)) ||
      (st = core_check_range(err, "adam decay_gamma", o->decay_gamma, 1e-30, 1.0)))
    return st;
  if (o->beta1 >= 1.0f || o->beta2 >= 1.0f)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "adam betas must be < 1");
  return NBRDF_OK;
}

nbrdf_status nn_adam_create(size_t n, const nn_adam_options *opts, nn_adam **out,
                            nbrdf_error *err) {
  *out = NULL;
  nn_adam_options defaults = NBRDF_ADAM_OPTIONS_DEFAULT;
  if (!opts) opts = &defaults;
  nbrdf_status st = check_options(opts, err);
  if (st != NBRDF_OK) return st;
  if (n == 0) return core_fail(err, NBRDF_ERR_ARGUMENT, "adam: no parameters to optimise");
  nn_adam *a = calloc(1, sizeof *a);
  if (a) {
    a->opts = *opts;
    a->n = n;
    a->m = calloc(n, sizeof *a->m);
    a->v = calloc(n, sizeof *a->v);
    a->groups = malloc(sizeof *a->groups);
  }
  if (!a || !a->m || !a->v || !a->groups) {
    nn_adam_destroy(a);
    return core_fail(err, NBRDF_ERR_MEMORY, "adam: out of memory for %zu parameters", n);
  }
  a->groups[0].lr = opts->lr;
  a->groups[0].weight_decay = opts->weight_decay;
  a->n_groups = 1;
  *out = a;
  return NBRDF_OK;
}

void nn_adam_destroy(nn_adam *adam) {
  if (!adam) return;
  free(adam->m);
  free(adam->v);
  free(adam->group_of);
  free(adam->groups);
  free(adam);
}

nbrdf_status nn_adam_add_group(nn_adam *adam, size_t offset, size_t count, float lr,
                               float weight_decay, int *group, nbrdf_error *err) {
  nbrdf_status st;
  if ((st = core_check_range(err, "adam group lr", lr, 0.0, 1e6)) ||
      (st = core_check_range(err, "adam group weight_decay", weight_decay, 0.0, 1e6)))
    return st;
  if (offset > adam->n || count > adam->n - offset || count == 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "adam group [%zu, %zu) is empty or outside the %zu parameters", offset,
                     offset + count, adam->n);
  if (adam->n_groups >= MAX_GROUPS)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "adam: more than %d groups", MAX_GROUPS - 1);
  if (!adam->group_of && !(adam->group_of = calloc(adam->n, sizeof *adam->group_of)))
    return core_fail(err, NBRDF_ERR_MEMORY, "adam: out of memory for groups");
  adam_group *g = realloc(adam->groups, sizeof *g * (size_t)(adam->n_groups + 1));
  if (!g) return core_fail(err, NBRDF_ERR_MEMORY, "adam: out of memory for groups");
  adam->groups = g;
  int id = adam->n_groups++;
  g[id].lr = lr;
  g[id].weight_decay = weight_decay;
  for (size_t i = offset; i < offset + count; i++)
    adam->group_of[i] = (uint16_t)id;
  if (group) *group = id;
  return NBRDF_OK;
}

nbrdf_status nn_adam_add_group_tensors(nn_adam *adam, const nn_network *nn, const char *name_part,
                                       float lr, float weight_decay, int *group, nbrdf_error *err) {
  if (nn->n_params != adam->n)
    return core_fail(err, NBRDF_ERR_MISMATCH, "adam has %zu parameters but the network has %zu",
                     adam->n, nn->n_params);
  int id = -1;
  for (int k = 0; k < nn->n_tensors; k++) {
    const nn_tensor *t = &nn->tensors[k];
    if (!strstr(t->name, name_part)) continue;
    if (id < 0) {
      nbrdf_status st = nn_adam_add_group(adam, t->offset, t->count, lr, weight_decay, &id, err);
      if (st != NBRDF_OK) return st;
    } else {
      for (size_t i = t->offset; i < t->offset + t->count; i++)
        adam->group_of[i] = (uint16_t)id;
    }
  }
  if (id < 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "adam: no tensor name contains \"%s\"", name_part);
  if (group) *group = id;
  return NBRDF_OK;
}

/* Step decay of the paper: lr * gamma^floor(t / decay_every). */
static double schedule(const nn_adam *adam, int64_t t) {
  if (adam->opts.decay_every <= 0) return 1.0;
  return pow(adam->opts.decay_gamma, (double)(t / adam->opts.decay_every));
}

float nn_adam_lr(const nn_adam *adam, int group) {
  if (group < 0 || group >= adam->n_groups) return 0.0f;
  return (float)(adam->groups[group].lr * schedule(adam, adam->t));
}

int64_t nn_adam_steps(const nn_adam *adam) { return adam->t; }

float *nn_adam_moment(nn_adam *adam, int second) { return second ? adam->v : adam->m; }
size_t nn_adam_size(const nn_adam *adam) { return adam->n; }
void nn_adam_set_steps(nn_adam *adam, int64_t steps) { adam->t = steps; }

void nn_adam_reset(nn_adam *adam) {
  memset(adam->m, 0, sizeof *adam->m * adam->n);
  memset(adam->v, 0, sizeof *adam->v * adam->n);
  adam->t = 0;
}

/* The update of one run of parameters sharing lr and weight decay. */
NN_HOT static void step_run(nn_adam *a, float *p, const float *g, size_t from, size_t to,
                     const adam_group *grp, double sched, double bc1, double bc2) {
  const float b1 = a->opts.beta1, b2 = a->opts.beta2, eps = a->opts.eps;
  /* Folding the bias corrections into the step size and eps (Kingma & Ba, end of Sec. 2). */
  const float lr = (float)(grp->lr * sched);
  const float step = (float)(grp->lr * sched / bc1);
  const float inv_sqrt_bc2 = (float)(1.0 / sqrt(bc2));
  const float decay = 1.0f - lr * grp->weight_decay;
  float *restrict m = a->m + from, *restrict v = a->v + from, *restrict pp = p + from;
  const float *restrict gg = g + from;
  size_t n = to - from;
  for (size_t i = 0; i < n; i++) {
    m[i] = b1 * m[i] + (1.0f - b1) * gg[i];
    v[i] = b2 * v[i] + (1.0f - b2) * gg[i] * gg[i];
    pp[i] = pp[i] * decay - step * m[i] / (sqrtf(v[i]) * inv_sqrt_bc2 + eps);
  }
}

/* Index of the first gradient that is Inf or NaN, or n. The scan is a branch-free OR of the
 * exponent bits per block (vectorised); only a block that has one is searched again. */
NN_HOT static size_t first_non_finite(const float *g, size_t n) {
  const uint32_t exp = 0x7f800000u;
  for (size_t i0 = 0; i0 < n; i0 += 4096) {
    size_t i1 = n - i0 < 4096 ? n : i0 + 4096;
    uint32_t bad = 0;
    for (size_t i = i0; i < i1; i++) {
      uint32_t u;
      memcpy(&u, g + i, sizeof u);
      bad |= (u & exp) == exp;
    }
    if (bad)
      for (size_t i = i0; i < i1; i++)
        if (!isfinite(g[i])) return i;
  }
  return n;
}

nbrdf_status nn_adam_step(nn_adam *adam, float *params, const float *grads, nbrdf_error *err) {
  size_t bad = first_non_finite(grads, adam->n);
  if (bad < adam->n)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "adam: gradient %zu is %g; no parameter was updated",
                     bad, (double)grads[bad]);
  double sched = schedule(adam, adam->t);
  adam->t++;
  double bc1 = 1.0 - pow(adam->opts.beta1, (double)adam->t);
  double bc2 = 1.0 - pow(adam->opts.beta2, (double)adam->t);
  if (!adam->group_of) {
    step_run(adam, params, grads, 0, adam->n, &adam->groups[0], sched, bc1, bc2);
    return NBRDF_OK;
  }
  for (size_t i = 0; i < adam->n;) {
    size_t j = i + 1;
    uint16_t id = adam->group_of[i];
    while (j < adam->n && adam->group_of[j] == id)
      j++;
    step_run(adam, params, grads, i, j, &adam->groups[id], sched, bc1, bc2);
    i = j;
  }
  return NBRDF_OK;
}
