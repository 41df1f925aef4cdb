/* core/linalg.h against closed forms. No network is involved, but the
 * Jacobi rotations and the elimination round: values are compared within
 * 1e-12 (relative to the matrices' unit-scale entries), far above the double
 * rounding of a few hundred operations and far below any real error. */
#include <math.h>
#include <string.h>

#include "core/linalg.h"
#include "core/rng.h"
#include "testing.h"

#define TOL 1e-12

static void test_eigen_diagonal(void) {
  double a[9] = {3, 0, 0, 0, -1, 0, 0, 0, 2}, ev[3], v[9];
  core_linalg_symmetric_eigen(a, 3, ev, v);
  CHECK(ev[0] == 3 && ev[1] == -1 && ev[2] == 2);
  for (int i = 0; i < 9; i++)
    CHECK(v[i] == (i % 4 == 0)); /* identity: already diagonal, no rotation */
}

static void test_eigen_2x2_closed_form(void) {
  /* [[a b] [b c]]: λ = (a+c)/2 ± sqrt(((a-c)/2)^2 + b^2). */
  const double a0 = 2.0, b0 = 1.5, c0 = -0.5;
  double a[4] = {a0, b0, b0, c0}, ev[2], v[4];
  core_linalg_symmetric_eigen(a, 2, ev, v);
  double m = 0.5 * (a0 + c0), r = sqrt(0.25 * (a0 - c0) * (a0 - c0) + b0 * b0);
  double hi = ev[0] > ev[1] ? ev[0] : ev[1], lo = ev[0] > ev[1] ? ev[1] : ev[0];
  CHECK_NEAR(hi, m + r, TOL);
  CHECK_NEAR(lo, m - r, TOL);
  /* Each column is an eigenvector: A v = λ v. */
  for (int j = 0; j < 2; j++) {
    CHECK_NEAR(a0 * v[0 * 2 + j] + b0 * v[1 * 2 + j], ev[j] * v[0 * 2 + j], TOL);
    CHECK_NEAR(b0 * v[0 * 2 + j] + c0 * v[1 * 2 + j], ev[j] * v[1 * 2 + j], TOL);
  }
}

static void random_symmetric(core_rng *rng, int n, double *a) {
  for (int i = 0; i < n; i++)
    for (int j = 0; j <= i; j++)
      a[i * n + j] = a[j * n + i] = 2.0 * core_rng_uniform(rng) - 1.0;
}

static void test_eigen_reconstructs_orthonormal(void) {
  enum { N = 32 }; /* the latent dimension the bake decomposes */
  static double a[N * N], work[N * N], v[N * N], ev[N];
  core_rng rng;
  core_rng_init(&rng, 11, 0);
  random_symmetric(&rng, N, a);
  memcpy(work, a, sizeof a);
  core_linalg_symmetric_eigen(work, N, ev, v);
  double worst_rec = 0.0, worst_orth = 0.0;
  for (int i = 0; i < N; i++)
    for (int j = 0; j < N; j++) {
      double rec = 0.0, dot = 0.0;
      for (int k = 0; k < N; k++)
        rec += v[i * N + k] * ev[k] * v[j * N + k], dot += v[k * N + i] * v[k * N + j];
      worst_rec = fmax(worst_rec, fabs(rec - a[i * N + j]));
      worst_orth = fmax(worst_orth, fabs(dot - (i == j)));
    }
  CHECK_MSG(worst_rec < 1e-10, "V diag(ev) Vᵀ differs from A by %g", worst_rec);
  CHECK_MSG(worst_orth < 1e-12, "VᵀV differs from I by %g", worst_orth);
  /* The eigenvalues' sum is the trace. */
  double tr = 0.0, sum = 0.0;
  for (int i = 0; i < N; i++)
    tr += a[i * N + i], sum += ev[i];
  CHECK_NEAR(sum, tr, 1e-10);
}

static void test_invert_2x2_closed_form(void) {
  double a[4] = {4, 7, 2, 6}, inv[4];
  CHECK(core_linalg_invert(a, 2, inv));
  const double det = 4.0 * 6.0 - 7.0 * 2.0;
  const double want[4] = {6 / det, -7 / det, -2 / det, 4 / det};
  for (int i = 0; i < 4; i++)
    CHECK_NEAR(inv[i], want[i], TOL);
}

static void test_invert_product_identity(void) {
  enum { N = 8 }; /* BAKE_COMPACT_MAX_DIM */
  double a[N * N], work[N * N], inv[N * N];
  core_rng rng;
  core_rng_init(&rng, 5, 1);
  for (int i = 0; i < N * N; i++)
    a[i] = 2.0 * core_rng_uniform(&rng) - 1.0 + (i % (N + 1) == 0 ? 4.0 : 0.0);
  memcpy(work, a, sizeof a);
  CHECK(core_linalg_invert(work, N, inv));
  double worst = 0.0;
  for (int i = 0; i < N; i++)
    for (int j = 0; j < N; j++) {
      double s = 0.0;
      for (int k = 0; k < N; k++)
        s += a[i * N + k] * inv[k * N + j];
      worst = fmax(worst, fabs(s - (i == j)));
    }
  CHECK_MSG(worst < TOL, "A inv(A) differs from I by %g", worst);
}

static void test_invert_needs_pivoting_and_refuses_singular(void) {
  double a[4] = {0, 1, 1, 0}, inv[4]; /* a zero first pivot: rows swap */
  CHECK(core_linalg_invert(a, 2, inv));
  CHECK(inv[0] == 0 && inv[1] == 1 && inv[2] == 1 && inv[3] == 0);
  double s[4] = {1, 2, 2, 4};
  CHECK(!core_linalg_invert(s, 2, inv));
  double z[1] = {0};
  CHECK(!core_linalg_invert(z, 1, inv));
}

int main(void) {
  RUN(test_eigen_diagonal);
  RUN(test_eigen_2x2_closed_form);
  RUN(test_eigen_reconstructs_orthonormal);
  RUN(test_invert_2x2_closed_form);
  RUN(test_invert_product_identity);
  RUN(test_invert_needs_pivoting_and_refuses_singular);
  return testing_finish();
}
