#include "bake/bake_auto.h"

#include <stdio.h>
#include <string.h>

#include "core/error.h"

static void append(char *buf, size_t cap, const char *fmt, double a, const char *s) {
  size_t len = strlen(buf);
  if (len + 1 >= cap) return;
  if (s)
    snprintf(buf + len, cap - len, fmt, s, a);
  else
    snprintf(buf + len, cap - len, fmt, a);
}

void bake_auto_describe(const bake_auto_outcome *a, char *buf, size_t cap) {
  snprintf(buf, cap, "chosen=%s; maxError=%g; met=%d; tried=", nbrdf_bake_accuracy_name(a->chosen),
           100.0 * a->max_error, a->met);
  for (int i = 0; i < a->tried; i++)
    append(buf, cap, i ? ",%s:%.2f" : "%s:%.2f", 100.0 * a->error[i],
           nbrdf_bake_accuracy_name(a->level[i]));
  if (!a->met) append(buf, cap, "; suggestedBudget=%g", a->suggested_budget, NULL);
}

void bake_auto_message(const bake_auto_outcome *a, char *buf, size_t cap) {
  char tried[256] = "";
  for (int i = 0; i < a->tried; i++)
    append(tried, sizeof tried, i ? ", %s %.2f %%" : "%s %.2f %%", 100.0 * a->error[i],
           nbrdf_bake_accuracy_name(a->level[i]));
  size_t best = 0;
  for (int i = 1; i < a->tried; i++)
    if (a->level[i] == a->chosen) best = (size_t)i;
  if (a->met) {
    snprintf(buf, cap, "auto: chose %s, held-out lobe error %.2f %% <= %g %% (tried: %s)",
             nbrdf_bake_accuracy_name(a->chosen), 100.0 * a->error[best], 100.0 * a->max_error,
             tried);
    return;
  }
  char budget[160];
  if (a->suggested_budget > 0.0)
    snprintf(budget, sizeof budget, "a --budget of about %g s would likely reach it",
             a->suggested_budget);
  else
    snprintf(budget, sizeof budget,
             "a larger --budget is unlikely to help (the plan already fits every distinct "
             "tuple at the most steps)");
  snprintf(buf, cap,
           "auto: no level within the budget meets %g %%: the best reached is %s at %.2f %% "
           "(tried: %s); %s",
           100.0 * a->max_error, nbrdf_bake_accuracy_name(a->chosen), 100.0 * a->error[best], tried,
           budget);
}

/* Tries `level` at the budget: its fit into `r` and its figures into `a`. */
static nbrdf_status try_level(const nbrdf_model *model, const bake_scene *scenes, size_t n_scenes,
                              const nbrdf_bake_options *o, nbrdf_bake_accuracy level,
                              core_ticker *ticker, bake_fit_result *r, bake_auto_outcome *a,
                              nbrdf_error *err) {
  nbrdf_bake_options lo = *o;
  lo.accuracy = level;
  if (level != NBRDF_BAKE_COMPACT) lo.compact_dim = lo.compact_width = 0;
  nbrdf_status st = bake_accuracy_fit(model, scenes, n_scenes, &lo, ticker, r, err);
  if (st != NBRDF_OK) return st;
  a->level[a->tried] = level;
  a->error[a->tried] = r->heldout_error;
  a->worse[a->tried] = bake_fit_worse_than_fast(r);
  a->tried++;
  if (o->warning && bake_fit_creates_energy(r)) {
    char why[512], msg[640];
    bake_fit_energy_message(r, level, why, sizeof why);
    snprintf(msg, sizeof msg, "auto: %s not chosen: %s", nbrdf_bake_accuracy_name(level), why);
    o->warning(o->user, msg);
  }
  return NBRDF_OK;
}

/* A level's budget too small for its smallest plan: not tried (the others may be). */
static int affordable(const nbrdf_model *model, const nbrdf_bake_options *o,
                      nbrdf_bake_accuracy level) {
  nbrdf_bake_options lo = *o;
  lo.accuracy = level;
  nbrdf_error e;
  return bake_accuracy_check(model, &lo, &e) == NBRDF_OK;
}

nbrdf_status bake_auto_choose(const nbrdf_model *model, const bake_scene *scenes, size_t n_scenes,
                              const nbrdf_bake_options *o, core_ticker *ticker, bake_fit_result *r,
                              bake_auto_outcome *a, nbrdf_error *err) {
  memset(r, 0, sizeof *r);
  memset(a, 0, sizeof *a);
  a->max_error = o->max_error / 100.0;
  a->budget = o->budget;
  double fast = 0.0;
  size_t held = 0;
  nbrdf_status st =
      bake_accuracy_fast_error(model, scenes, n_scenes, o, ticker, &fast, &held, &a->distinct, err);
  if (st != NBRDF_OK) return st;
  a->level[0] = NBRDF_BAKE_FAST, a->error[0] = fast, a->tried = 1;
  a->chosen = NBRDF_BAKE_FAST;
  r->heldout = held, r->heldout_error = r->heldout_error_fast = fast;
  r->distinct = a->distinct;
  double best = fast;
  if (fast <= a->max_error) {
    a->met = 1;
    return NBRDF_OK;
  }
  static const nbrdf_bake_accuracy ladder[] = {NBRDF_BAKE_FITTED, NBRDF_BAKE_SPECIALISED};
  for (size_t i = 0; i < sizeof ladder / sizeof *ladder && !a->met; i++) {
    if (!affordable(model, o, ladder[i])) continue;
    bake_fit_result t;
    st = try_level(model, scenes, n_scenes, o, ladder[i], ticker, &t, a, err);
    if (st != NBRDF_OK) break;
    const int k = a->tried - 1;
    if (!a->worse[k] && a->error[k] < best) {
      bake_fit_result_free(r);
      *r = t, best = a->error[k], a->chosen = ladder[i];
      a->met = best <= a->max_error;
    } else {
      bake_fit_result_free(&t);
    }
  }
  /* Compact-or-not: asked for with compact_dim, the compact level is taken when it too meets
   * the target (a smaller texture and decoder for the same promise). */
  if (st == NBRDF_OK && a->met && o->compact_dim > 0 && a->chosen == NBRDF_BAKE_SPECIALISED &&
      affordable(model, o, NBRDF_BAKE_COMPACT)) {
    bake_fit_result t;
    st = try_level(model, scenes, n_scenes, o, NBRDF_BAKE_COMPACT, ticker, &t, a, err);
    const int k = a->tried - 1;
    if (st == NBRDF_OK && !a->worse[k] && a->error[k] <= a->max_error) {
      bake_fit_result_free(r);
      *r = t, a->chosen = NBRDF_BAKE_COMPACT;
    } else if (st == NBRDF_OK) {
      bake_fit_result_free(&t);
    }
  }
  if (st != NBRDF_OK) {
    bake_fit_result_free(r);
    return st;
  }
  if (!a->met) {
    nbrdf_bake_accuracy top = a->chosen == NBRDF_BAKE_FAST ? NBRDF_BAKE_SPECIALISED : a->chosen;
    nbrdf_bake_options lo = *o;
    lo.accuracy = top;
    a->suggested_budget = bake_accuracy_budget_for(model, top, bake_accuracy_budget(&lo),
                                                   a->distinct, best, a->max_error);
    if (o->require) {
      char msg[512];
      bake_auto_message(a, msg, sizeof msg);
      bake_fit_result_free(r);
      return core_fail(err, NBRDF_ERR_UNSUPPORTED, "bake: %s (required: nothing written)", msg);
    }
  }
  return NBRDF_OK;
}
