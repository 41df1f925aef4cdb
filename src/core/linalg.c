#include "core/linalg.h"

#include <math.h>

void core_linalg_symmetric_eigen(double *a, int D, double *ev, double *v) {
  for (int i = 0; i < D; i++)
    for (int j = 0; j < D; j++)
      v[i * D + j] = i == j;
  for (int sweep = 0; sweep < 100; sweep++) {
    double off = 0.0, diag = 0.0;
    for (int i = 0; i < D; i++)
      for (int j = 0; j < D; j++)
        *(i == j ? &diag : &off) += a[i * D + j] * a[i * D + j];
    if (off <= 1e-24 * (diag > 0 ? diag : 1.0)) break;
    for (int p = 0; p < D; p++)
      for (int q = p + 1; q < D; q++) {
        double apq = a[p * D + q];
        if (fabs(apq) < 1e-300) continue;
        double theta = (a[q * D + q] - a[p * D + p]) / (2.0 * apq);
        double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
        double cs = 1.0 / sqrt(t * t + 1.0), sn = t * cs;
        for (int k = 0; k < D; k++) { /* columns p, q */
          double akp = a[k * D + p], akq = a[k * D + q];
          a[k * D + p] = cs * akp - sn * akq;
          a[k * D + q] = sn * akp + cs * akq;
        }
        for (int k = 0; k < D; k++) { /* rows p, q */
          double apk = a[p * D + k], aqk = a[q * D + k];
          a[p * D + k] = cs * apk - sn * aqk;
          a[q * D + k] = sn * apk + cs * aqk;
        }
        for (int k = 0; k < D; k++) {
          double vkp = v[k * D + p], vkq = v[k * D + q];
          v[k * D + p] = cs * vkp - sn * vkq;
          v[k * D + q] = sn * vkp + cs * vkq;
        }
      }
  }
  for (int i = 0; i < D; i++)
    ev[i] = a[i * D + i];
}

int core_linalg_invert(double *a, int K, double *inv) {
  for (int r = 0; r < K; r++)
    for (int k = 0; k < K; k++)
      inv[r * K + k] = r == k;
  for (int c = 0; c < K; c++) {
    int p = c;
    for (int r = c + 1; r < K; r++)
      if (fabs(a[r * K + c]) > fabs(a[p * K + c])) p = r;
    if (!(fabs(a[p * K + c]) > 1e-12)) return 0;
    for (int k = 0; k < K; k++) {
      double t = a[c * K + k];
      a[c * K + k] = a[p * K + k], a[p * K + k] = t;
      t = inv[c * K + k];
      inv[c * K + k] = inv[p * K + k], inv[p * K + k] = t;
    }
    double d = a[c * K + c];
    for (int k = 0; k < K; k++)
      a[c * K + k] /= d, inv[c * K + k] /= d;
    for (int r = 0; r < K; r++) {
      double f = r == c ? 0.0 : a[r * K + c];
      for (int k = 0; f != 0.0 && k < K; k++)
        a[r * K + k] -= f * a[c * K + k], inv[r * K + k] -= f * inv[c * K + k];
    }
  }
  return 1;
}
