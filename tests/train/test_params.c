/* Table 2 parameter draws: ranges, moments, determinism, seed families. */
#include <math.h>
#include <string.h>

#include "testing.h"
#include "train/params.h"

enum { N = 20000 };

static void test_table2_moments(void) {
  double sa = 0, se = 0, sA = 0, sr = 0, ss[4] = {0};
  double amin = 1, amax = 0;
  uint64_t fam = train_family_seed(7);
  for (int k = 0; k < N; k++) {
    train_params p;
    train_params_draw(fam, TRAIN_LAYERED2, (uint64_t)k, &p);
    const train_coat *c = &p.coat[0];
    CHECK(p.kind == TRAIN_LAYERED2 && p.n_coats == 1);
    CHECK(c->alpha >= 0.216 * 0.216 * 0.216 && c->alpha < 1.0);
    CHECK(c->eta >= 1.05 && c->eta < 2.0);
    CHECK(c->albedo > 0.0 && c->albedo <= 1.0);
    CHECK(p.base_r0 >= 0.0 && p.base_r0 < 1.0);
    CHECK(p.base_alpha >= 0.01 && p.base_alpha < 1.0);
    amin = fmin(amin, c->alpha), amax = fmax(amax, c->alpha);
    sa += c->alpha, se += c->eta, sA += c->albedo, sr += p.base_r0;
    int i = c->sigma_t == 0 ? 0 : c->sigma_t == 1 ? 1 : c->sigma_t == 2 ? 2 : 3;
    CHECK(c->sigma_t == 0 || c->sigma_t == 1 || c->sigma_t == 2 || c->sigma_t == 5);
    ss[i] += 1;
  }
  /* E[t^3], t ~ U(0.216, 1): (1 - 0.216^4) / (4 · 0.784). */
  double ea = (1.0 - pow(0.216, 4)) / (4.0 * 0.784);
  CHECK_NEAR(sa / N, ea, 0.006);
  CHECK_NEAR(se / N, 1.525, 0.006);
  CHECK_NEAR(sA / N, 2.0 / 3.0, 0.006);
  CHECK_NEAR(sr / N, 0.5, 0.006);
  for (int i = 0; i < 4; i++)
    CHECK_NEAR(ss[i] / N, 0.25, 0.012);
  CHECK(amin < 0.012 && amax > 0.97);
}

static void test_draw_functions(void) {
  CHECK_NEAR(train_draw_alpha(0.0), 0.010077696, 1e-9);
  CHECK(train_draw_alpha(0.999999) < 1.0);
  CHECK_NEAR(train_draw_eta(0.0), 1.05, 1e-12);
  CHECK_NEAR(train_draw_albedo(0.0), 1.0, 1e-12);
  CHECK(train_draw_sigma_t(0.0) == 0.0 && train_draw_sigma_t(0.999) == 5.0);
  CHECK(train_draw_sigma_t(0.3) == 1.0 && train_draw_sigma_t(0.6) == 2.0);
}

static void test_determinism_and_families(void) {
  train_params a, b;
  train_params_draw(train_family_seed(3), TRAIN_LAYERED3, 41, &a);
  train_params_draw(train_family_seed(3), TRAIN_LAYERED3, 41, &b);
  CHECK(memcmp(&a, &b, sizeof a) == 0);
  train_params_draw(train_family_seed(4), TRAIN_LAYERED3, 41, &b);
  CHECK(a.coat[0].alpha != b.coat[0].alpha);
  train_params_draw(train_family_seed(3), TRAIN_LAYERED3, 42, &b);
  CHECK(a.coat[0].alpha != b.coat[0].alpha);
  CHECK(a.n_coats == 2 && a.coat[1].eta >= 1.05);
  train_params_draw(train_family_seed(3), TRAIN_LAYERED2, 41, &b);
  CHECK_MSG(a.coat[0].alpha != b.coat[0].alpha, "layered2 and layered3 share a coat");
  /* Held-out families never coincide with training ones for small seeds,
   * nor with each other. */
  for (int set = 1; set <= 4; set++) {
    uint64_t h = train_heldout_seed((train_heldout)set);
    for (uint64_t s = 0; s < 10000; s++)
      CHECK(h != train_family_seed(s));
    for (int o = 1; o < set; o++)
      CHECK(h != train_heldout_seed((train_heldout)o));
  }
  CHECK(train_heldout_kind(TRAIN_HELDOUT_LAYER3) == TRAIN_LAYERED3);
  CHECK(train_heldout_kind(TRAIN_HELDOUT_SINGLE) == TRAIN_SINGLE);
}

static void test_single_mixes_and_creates(void) {
  int kinds[2] = {0, 0};
  uint64_t fam = train_heldout_seed(TRAIN_HELDOUT_SINGLE);
  for (int k = 0; k < 200; k++) {
    train_params p;
    train_params_draw(fam, TRAIN_SINGLE, (uint64_t)k, &p);
    CHECK(p.kind == TRAIN_CONDUCTOR || p.kind == TRAIN_DIELECTRIC);
    kinds[p.kind == TRAIN_DIELECTRIC]++;
    if (p.kind == TRAIN_DIELECTRIC) CHECK(p.base_eta >= 1.05 && p.base_eta < 2.0);
  }
  CHECK(kinds[0] > 70 && kinds[1] > 70);
  for (int kind = 0; kind < 4; kind++) {
    train_params p;
    nbrdf_brdf *b = NULL;
    nbrdf_error err;
    train_params_draw(train_family_seed(1), (train_kind)kind, 0, &p);
    CHECK_OK(train_params_create(&p, &b, &err), &err);
    CHECK(b && nbrdf_brdf_is_stochastic(b) == (kind >= TRAIN_LAYERED2));
    nbrdf_brdf_destroy(b);
  }
  CHECK(train_kind_parse("layered3") == TRAIN_LAYERED3 && train_kind_parse("x") == -1);
}

/* The coverage distribution: its shares of η = 1, η ∈ [1, 1.2] and α ≤ 0.03
 * on coats (within 3σ of a binomial over 20,000 draws), Table 2 below, and
 * every value inside the ground truth's ranges. */
static void test_coverage_draws(void) {
  const int n = 20000;
  int eta1 = 0, eta_low = 0, sharp = 0, base_sharp = 0;
  uint64_t fam = train_family_seed(5);
  for (int i = 0; i < n; i++) {
    train_params p;
    train_params_draw_from(fam, TRAIN_LAYERED2, TRAIN_DRAWS_COVERAGE, (uint64_t)i, &p);
    const train_coat *c = &p.coat[0];
    CHECK(c->eta >= 1.0 && c->eta <= 2.0 && c->alpha >= 0.01 && c->alpha <= 1.0);
    eta1 += c->eta == 1.0;
    eta_low += c->eta <= 1.2;
    sharp += c->alpha <= 0.03;
    base_sharp += p.base_alpha <= 0.03;
  }
  double sd = sqrt(0.25 / n) * 3.0;
  CHECK_NEAR((double)eta1 / n, 0.05, sd);
  CHECK_NEAR((double)eta_low / n, 0.20, sd);
  CHECK_NEAR((double)sharp / n, 0.15, sd);
  /* Table 2's cube law gives α ≤ 0.03 (cbrt(0.03) − 0.216) / 0.784 ≈ 12.1 %. */
  CHECK_NEAR((double)base_sharp / n, (cbrt(0.03) - 0.216) / 0.784, sd);
  CHECK_NEAR(train_draw_alpha_coverage(0.0), 0.01, 1e-12);
  CHECK_NEAR(train_draw_alpha_coverage(0.15), 0.03, 1e-9);
  CHECK_NEAR(train_draw_alpha_coverage(0.999999), 1.0, 1e-5);
  CHECK(train_draw_eta_coverage(0.01) == 1.0);
  CHECK_NEAR(train_draw_eta_coverage(0.2), 1.2, 1e-12);
  /* Table 2 draws are unchanged by the new entry point. */
  train_params a, b;
  train_params_draw(fam, TRAIN_LAYERED3, 7, &a);
  train_params_draw_from(fam, TRAIN_LAYERED3, TRAIN_DRAWS_TABLE2, 7, &b);
  CHECK(!memcmp(&a, &b, sizeof a));
  nbrdf_brdf *brdf = NULL;
  nbrdf_error err = {0};
  for (int i = 0; i < 200; i++) {
    train_params p;
    train_params_draw_from(fam, TRAIN_SINGLE, TRAIN_DRAWS_COVERAGE, (uint64_t)i, &p);
    CHECK_OK(train_params_create(&p, &brdf, &err), &err);
    nbrdf_brdf_destroy(brdf);
  }
  CHECK(train_draws_parse("coverage") == TRAIN_DRAWS_COVERAGE && train_draws_parse("x") == -1);
}

/* The tails distribution: every draw in its region (by index), each region's
 * ranges reached at both ends, and the regions' names. */
static void test_tails_draws(void) {
  uint64_t fam = train_heldout_seed(TRAIN_HELDOUT_TAILS);
  double lo[3][2] = {{9, 9}, {9, 9}, {9, 9}}, hi[3][2] = {{0}}; /* [region][alpha, eta] */
  for (int i = 0; i < 3000; i++) {
    train_params p;
    train_params_draw_from(fam, TRAIN_LAYERED2, TRAIN_DRAWS_TAILS, (uint64_t)i, &p);
    const train_coat *c = &p.coat[0];
    int g = train_tails_region((uint64_t)i);
    CHECK(g == i % 3);
    CHECK(c->alpha >= 0.01 && c->alpha <= 1.0 && c->eta >= 1.0 && c->eta <= 2.0);
    if (g == 0) CHECK(c->eta <= 1.2 && c->alpha > 0.05);
    if (g == 1) CHECK(c->eta >= 1.2 && c->alpha <= 0.05);
    if (g == 2) CHECK(c->eta <= 1.2 && c->alpha <= 0.05);
    double v[2] = {c->alpha, c->eta};
    for (int k = 0; k < 2; k++)
      lo[g][k] = fmin(lo[g][k], v[k]), hi[g][k] = fmax(hi[g][k], v[k]);
    CHECK(p.base_r0 >= 0.0 && p.base_r0 <= 1.0 && p.base_alpha >= 0.01);
  }
  CHECK(lo[0][0] < 0.06 && hi[0][0] > 0.9 && lo[0][1] < 1.01 && hi[0][1] > 1.19);
  CHECK(lo[1][0] < 0.011 && hi[1][0] > 0.048 && lo[1][1] < 1.21 && hi[1][1] > 1.98);
  CHECK(lo[2][0] < 0.011 && hi[2][0] > 0.048 && lo[2][1] < 1.01 && hi[2][1] > 1.19);
  CHECK(train_draws_parse("tails") == TRAIN_DRAWS_TAILS);
  CHECK(!strcmp(train_tails_region_name(1), "alpha1<=0.05"));
  /* its own held-out family: not the layer set's BRDFs */
  CHECK(train_heldout_seed(TRAIN_HELDOUT_TAILS) != train_heldout_seed(TRAIN_HELDOUT_LAYER));
}

/* MIRROR: smooth bright conductor bases under coats half sharp, eta = 1 included. */
static void test_mirror_draws(void) {
  uint64_t fam = train_family_seed(6);
  int sharp = 0, no_coat = 0, n = 2000;
  double lo_a2 = 9, hi_a2 = 0, lo_r0 = 9;
  for (int i = 0; i < n; i++) {
    train_params p;
    train_params_draw_from(fam, TRAIN_LAYERED3, TRAIN_DRAWS_MIRROR, (uint64_t)i, &p);
    CHECK(p.base_alpha >= 0.01 && p.base_alpha <= 0.05 + 1e-12);
    CHECK(p.base_r0 > 0.8 && p.base_r0 <= 1.0);
    lo_a2 = fmin(lo_a2, p.base_alpha), hi_a2 = fmax(hi_a2, p.base_alpha);
    lo_r0 = fmin(lo_r0, p.base_r0);
    for (int c = 0; c < 2; c++) {
      CHECK(p.coat[c].alpha >= 0.01 && p.coat[c].alpha <= 1.0);
      CHECK(p.coat[c].eta >= 1.0 && p.coat[c].eta <= 2.0);
      sharp += p.coat[c].alpha <= 0.05, no_coat += p.coat[c].eta == 1.0;
    }
  }
  CHECK(lo_a2 < 0.011 && hi_a2 > 0.048 && lo_r0 < 0.81);
  /* half log-uniform on [0.01, 0.05] plus Table 2's own share below 0.05 (~22 % of it) */
  CHECK_MSG(sharp > 0.55 * 2 * n && sharp < 0.67 * 2 * n, "%d sharp coats of %d", sharp, 2 * n);
  CHECK_MSG(no_coat > 0.03 * 2 * n && no_coat < 0.07 * 2 * n, "%d eta = 1 of %d", no_coat, 2 * n);
  /* a dielectric alone keeps its own (coat-like) draws */
  train_params d;
  train_params_draw_from(fam, TRAIN_DIELECTRIC, TRAIN_DRAWS_MIRROR, 3, &d);
  CHECK(d.base_eta >= 1.0 && d.base_r0 == 0.0);
  CHECK(train_draws_parse("mirror") == TRAIN_DRAWS_MIRROR);
  CHECK(!strcmp(train_draws_name(TRAIN_DRAWS_MIRROR), "mirror"));
}

int main(void) {
  RUN(test_coverage_draws);
  RUN(test_tails_draws);
  RUN(test_mirror_draws);
  RUN(test_table2_moments);
  RUN(test_draw_functions);
  RUN(test_determinism_and_families);
  RUN(test_single_mixes_and_creates);
  return testing_finish();
}
