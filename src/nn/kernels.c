/* The element-wise and GEMM kernels of the layers. Everything outside the GEMMs is a few
 * passes over each row that the compiler vectorises. Sums within a row (at most a few hundred
 * terms) keep 16 independent float partial sums combined pairwise: vectorisable without
 * -ffast-math, two AVX registers deep, and bit-reproducible; LayerNorm's variance is two-pass.
 * Sums over the batch (bias, gamma and beta gradients) are kept in double because they run
 * over up to 65536 rows (LayerNorm's add blocks of 16 rows in float first). */
#include <cblas.h>
#include <math.h>
#include <string.h>

#include "nn/internal.h"

/* The project builds at -O2, where GCC 12 vectorises almost nothing; these loops are the
 * whole cost of a network outside the GEMMs (bench/bench_nn.c measures it). NN_HOT
 * (nn/internal.h) clones them per vector width: 16 partial sums are one AVX-512 register. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("O3")
#endif

#define LN_EPS 1e-5f
#define LANES 16
#define ROW_GROUP 8

void nn_gemm_xwt(int rows, int in, int out, const float *x, const float *w, float beta, float *y) {
  if (rows == 1) {
    /* A single query is a matrix-vector product; sgemm's packing would dominate. */
    cblas_sgemv(CblasRowMajor, CblasNoTrans, out, in, 1.0f, w, in, x, 1, beta, y, 1);
    return;
  }
  cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasTrans, rows, out, in, 1.0f, x, in, w, in, beta, y,
              out);
}

void nn_gemm_gw(int rows, int out, int in, const float *g, const float *w, float beta, float *dx) {
  cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, rows, in, out, 1.0f, g, out, w, in, beta,
              dx, in);
}

void nn_gemm_gtx(int rows, int out, int in, const float *g, const float *x, float *dw) {
  cblas_sgemm(CblasRowMajor, CblasTrans, CblasNoTrans, out, in, rows, 1.0f, g, out, x, in, 1.0f, dw,
              in);
}

#if defined(__GNUC__)
#define NN_INLINE static inline __attribute__((always_inline))
#else
#define NN_INLINE static inline
#endif

/* Pairwise sum of the partial sums (a tree, so that it maps onto vector shuffles). */
NN_INLINE float reduce_lanes(const float *p) {
  float q[LANES / 2];
  for (int k = 0; k < LANES / 2; k++)
    q[k] = p[k] + p[k + LANES / 2];
  for (int k = 0; k < LANES / 4; k++)
    q[k] += q[k + LANES / 4];
  for (int k = 0; k < LANES / 8; k++)
    q[k] += q[k + LANES / 8];
  return q[0] + q[1];
}

/* u += sum of `terms` in one vectorised pass (no branch inside the loop), returning sum(u). */
#define ADD_SUM_BODY(EXPR)                                                                         \
  do {                                                                                             \
    for (; c + LANES <= w; c += LANES)                                                             \
      for (int k = 0; k < LANES; k++) {                                                            \
        int i = c + k;                                                                             \
        float v = EXPR;                                                                            \
        u[i] = v;                                                                                  \
        part[k] += v;                                                                              \
      }                                                                                            \
    for (; c < w; c++) {                                                                           \
      int i = c;                                                                                   \
      float v = EXPR;                                                                              \
      u[i] = v;                                                                                    \
      tail += v;                                                                                   \
    }                                                                                              \
  } while (0)

/* u += bias + a1 + a2 (each may be NULL), returning the sum of the new u: one pass. */
NN_INLINE float add_sum_lanes(float *restrict u, const float *restrict bias,
                              const float *restrict a1, const float *restrict a2, int w) {
  float part[LANES] = {0}, tail = 0;
  int c = 0;
  if (!a1 && a2) a1 = a2, a2 = NULL;
  if (!bias)
    ADD_SUM_BODY(u[i]);
  else if (a2)
    ADD_SUM_BODY(u[i] + bias[i] + a1[i] + a2[i]);
  else if (a1)
    ADD_SUM_BODY(u[i] + bias[i] + a1[i]);
  else
    ADD_SUM_BODY(u[i] + bias[i]);
  return reduce_lanes(part) + tail;
}

NN_INLINE float sum_lanes(const float *v, int w) {
  float part[LANES] = {0};
  int c = 0;
  for (; c + LANES <= w; c += LANES)
    for (int k = 0; k < LANES; k++)
      part[k] += v[c + k];
  float s = reduce_lanes(part);
  for (; c < w; c++)
    s += v[c];
  return s;
}

NN_INLINE float sumsq_dev_lanes(const float *v, int w, float mean) {
  float part[LANES] = {0};
  int c = 0;
  for (; c + LANES <= w; c += LANES)
    for (int k = 0; k < LANES; k++) {
      float d = v[c + k] - mean;
      part[k] += d * d;
    }
  float s = reduce_lanes(part);
  for (; c < w; c++) {
    float d = v[c] - mean;
    s += d * d;
  }
  return s;
}

NN_INLINE float dot_lanes(const float *a, const float *b, int w) {
  float part[LANES] = {0};
  int c = 0;
  for (; c + LANES <= w; c += LANES)
    for (int k = 0; k < LANES; k++)
      part[k] += a[c + k] * b[c + k];
  float s = reduce_lanes(part);
  for (; c < w; c++)
    s += a[c] * b[c];
  return s;
}

/* In place: u = pre-normalisation sum on entry (GEMM output, without bias), xhat on return.
 * u += bias + add1 + add2 (residual and skips are added here, paper Fig. 3), then
 * xhat = (u - mean) / sqrt(var + eps) (two-pass, biased variance as PyTorch), and
 * y = [ReLU](xhat * gamma + beta). add1 and add2 may be NULL (and may be the same array). */
NN_HOT void nn_ln_forward(int rows, int w, float *restrict u_all, const float *restrict bias,
                          const float *restrict add1, const float *restrict add2,
                          const float *restrict gamma, const float *restrict beta,
                          float *restrict rstd, float *restrict y, int relu) {
  /* Rows go in groups of ROW_GROUP so that the square roots and divisions of a group are one
   * vector operation instead of a latency chain per row (narrow layers are dominated by it). */
  for (int r0 = 0; r0 < rows; r0 += ROW_GROUP) {
    int n = rows - r0 < ROW_GROUP ? rows - r0 : ROW_GROUP;
    float mean[ROW_GROUP], rs[ROW_GROUP];
    for (int k = 0; k < ROW_GROUP; k++)
      mean[k] = 0.0f, rs[k] = 1.0f;
    for (int k = 0; k < n; k++) {
      size_t at = (size_t)(r0 + k) * w;
      mean[k] =
          add_sum_lanes(u_all + at, bias, add1 ? add1 + at : NULL, add2 ? add2 + at : NULL, w) /
          (float)w;
      rs[k] = sumsq_dev_lanes(u_all + at, w, mean[k]) / (float)w;
    }
    for (int k = 0; k < ROW_GROUP; k++)
      rs[k] = 1.0f / sqrtf(rs[k] + LN_EPS);
    for (int k = 0; k < n; k++) {
      float *restrict u = u_all + (size_t)(r0 + k) * w;
      float *restrict yr = y + (size_t)(r0 + k) * w;
      float m = mean[k], s = rs[k];
      rstd[r0 + k] = s;
      if (relu)
        for (int c = 0; c < w; c++) {
          float xh = (u[c] - m) * s, v = xh * gamma[c] + beta[c];
          u[c] = xh;
          /* Written so that NaN passes through (maxps keeps its second operand). */
          yr[c] = 0.0f > v ? 0.0f : v;
        }
      else
        for (int c = 0; c < w; c++) {
          float xh = (u[c] - m) * s;
          u[c] = xh;
          yr[c] = xh * gamma[c] + beta[c];
        }
    }
  }
}

/* Rows whose column sums (dgamma, dbeta, dbias) add up in float before they join the double
 * accumulators: the per-element double conversion and add cost as much as the rest of the
 * backward pass, and 16 float terms lose nothing the double sum over the batch keeps. */
#define SUM_BLOCK 16

/* One row of LayerNorm backward (after the ReLU mask): dL/dy in gr on entry, dL/du on return.
 * Adds the row's dL/dy, dL/dy * xhat and dL/du to sb, sg and sd. */
NN_INLINE void ln_backward_row(int w, float *restrict gr, const float *restrict xr, float rs,
                               const float *restrict gamma, float *restrict dxh,
                               float *restrict sg, float *restrict sb, float *restrict sd) {
  /* dL/du = rstd * (dxh - mean(dxh) - xhat * mean(dxh * xhat)); both means in one pass, with
   * the lane layout of sum_lanes and dot_lanes. */
  float p1[LANES] = {0}, p2[LANES] = {0};
  int c = 0;
  for (; c + LANES <= w; c += LANES)
    for (int k = 0; k < LANES; k++) {
      int i = c + k;
      float gv = gr[i], xv = xr[i], d = gv * gamma[i];
      dxh[i] = d;
      p1[k] += d;
      p2[k] += d * xv;
      sb[i] += gv, sg[i] += gv * xv;
    }
  float s1 = reduce_lanes(p1), s2 = reduce_lanes(p2);
  for (; c < w; c++) {
    float gv = gr[c], xv = xr[c], d = gv * gamma[c];
    dxh[c] = d;
    s1 += d;
    s2 += d * xv;
    sb[c] += gv, sg[c] += gv * xv;
  }
  float m1 = s1 / (float)w, m2 = s2 / (float)w;
  for (c = 0; c < w; c++) {
    float v = rs * (dxh[c] - m1 - xr[c] * m2);
    gr[c] = v;
    sd[c] += v;
  }
}

/* In place: g = dL/dy on entry, dL/du on return (u the pre-normalisation sum). With y_relu,
 * y_relu is the layer's output and the ReLU's mask is y > 0. dgamma, dbeta and dbias (any may
 * be NULL; all NULL for a frozen network) accumulate the column sums of dL/dy * xhat, dL/dy and
 * dL/du. */
NN_HOT void nn_ln_backward(int rows, int w, float *restrict g, const float *restrict y_relu,
                           const float *restrict xhat, const float *restrict rstd,
                           const float *restrict gamma, double *restrict dgamma,
                           double *restrict dbeta, double *restrict dbias) {
  float dxh[NBRDF_NN_MAX_WIDTH], sg[NBRDF_NN_MAX_WIDTH], sb[NBRDF_NN_MAX_WIDTH],
      sd[NBRDF_NN_MAX_WIDTH];
  int sums = dgamma || dbeta || dbias;
  for (int r0 = 0; r0 < rows; r0 += SUM_BLOCK) {
    int r1 = rows - r0 < SUM_BLOCK ? rows : r0 + SUM_BLOCK;
    if (sums)
      for (int c = 0; c < w; c++)
        sg[c] = 0.0f, sb[c] = 0.0f, sd[c] = 0.0f;
    for (int r = r0; r < r1; r++) {
      float *restrict gr = g + (size_t)r * w;
      const float *restrict xr = xhat + (size_t)r * w;
      if (y_relu) {
        const float *restrict yr = y_relu + (size_t)r * w;
        for (int c = 0; c < w; c++)
          gr[c] = yr[c] > 0.0f ? gr[c] : 0.0f;
      }
      if (sums) {
        ln_backward_row(w, gr, xr, rstd[r], gamma, dxh, sg, sb, sd);
        continue;
      }
      /* Without sums, separate passes are faster (GCC vectorises the fused pass of
       * ln_backward_row worse without its column sums: 70 vs 31 ns a row of 64). */
      for (int c = 0; c < w; c++)
        dxh[c] = gr[c] * gamma[c];
      float m1 = sum_lanes(dxh, w) / (float)w;
      float m2 = dot_lanes(dxh, xr, w) / (float)w;
      float rs = rstd[r];
      for (int c = 0; c < w; c++)
        gr[c] = rs * (dxh[c] - m1 - xr[c] * m2);
    }
    if (dgamma)
      for (int c = 0; c < w; c++)
        dgamma[c] += sg[c];
    if (dbeta)
      for (int c = 0; c < w; c++)
        dbeta[c] += sb[c];
    if (dbias)
      for (int c = 0; c < w; c++)
        dbias[c] += sd[c];
  }
}

NN_HOT void nn_add_rows(int rows, int w, float *y, const float *bias, const float *add) {
  for (int r = 0; r < rows; r++) {
    float *yr = y + (size_t)r * w;
    if (bias)
      for (int c = 0; c < w; c++)
        yr[c] += bias[c];
    if (add) {
      const float *a = add + (size_t)r * w;
      for (int c = 0; c < w; c++)
        yr[c] += a[c];
    }
  }
}

NN_HOT void nn_relu_forward(size_t n, const float *x, float *y) {
  for (size_t i = 0; i < n; i++)
    y[i] = 0.0f > x[i] ? 0.0f : x[i];
}

NN_HOT void nn_relu_backward(size_t n, float *g, const float *y) {
  for (size_t i = 0; i < n; i++)
    g[i] = y[i] > 0.0f ? g[i] : 0.0f;
}

NN_HOT void nn_colsum(int rows, int w, const float *g, double *acc) {
  for (int r = 0; r < rows; r++) {
    const float *gr = g + (size_t)r * w;
    for (int c = 0; c < w; c++)
      acc[c] += gr[c];
  }
}

/* grad += acc, then acc = 0 for the next tensor. */
NN_HOT void nn_flush(int w, double *acc, float *grad) {
  for (int c = 0; c < w; c++) {
    grad[c] += (float)acc[c];
    acc[c] = 0.0;
  }
}
