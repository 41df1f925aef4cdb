#include "model/loss.h"

#include <math.h>
#include <string.h>

const char *model_loss_name(model_loss_kind kind) {
  return kind == MODEL_LOSS_L1 ? "l1" : "l1-log1p";
}

int model_loss_parse(const char *name, model_loss_kind *kind) {
  if (!strcmp(name, "l1-log1p")) {
    *kind = MODEL_LOSS_L1_LOG1P;
    return 1;
  }
  if (!strcmp(name, "l1")) {
    *kind = MODEL_LOSS_L1;
    return 1;
  }
  return 0;
}

static double sign(double x) { return (x > 0.0) - (x < 0.0); }

double model_loss_sum(model_loss_kind kind, model_output output, size_t n, const float *o,
                      const float *f, const float *w, float scale, float *dloss_do) {
  double total = 0.0;
  for (size_t r = 0; r < n; r++) {
    double x = o[r], pred, dpred, wr = w ? (double)w[r] : 1.0;
    if (kind == MODEL_LOSS_L1_LOG1P) {
      if (output == MODEL_OUTPUT_LOG1P)
        pred = x, dpred = 1.0;
      else if (x >= 0.0)
        pred = log1p(x), dpred = 1.0 / (1.0 + x);
      else
        pred = x, dpred = 1.0;
      double diff = pred - log1p((double)f[r]);
      total += wr * fabs(diff);
      if (dloss_do) dloss_do[r] = (float)(scale * wr * sign(diff) * dpred);
    } else {
      if (output == MODEL_OUTPUT_LOG1P) {
        double xc = fmin(x, 80.0);
        pred = expm1(xc), dpred = x < 80.0 ? exp(xc) : 0.0;
      } else {
        pred = x, dpred = 1.0;
      }
      double diff = pred - (double)f[r];
      total += wr * fabs(diff);
      if (dloss_do) dloss_do[r] = (float)(scale * wr * sign(diff) * dpred);
    }
  }
  return total;
}
