/* Losses of the decoder's raw output o against BRDF values f (>= 0), per row,
 * with the output transform of decoder.h taken into account:
 *
 * - MODEL_LOSS_L1_LOG1P (default): |c(o) − log(1 + f)| where c(o) is the
 *   prediction in log(1 + f) space: o itself for MODEL_OUTPUT_LOG1P; log(1 + o)
 *   for MODEL_OUTPUT_F, continued linearly (c = o) below 0 so that a negative
 *   prediction still has a gradient. DESIGN.md's measured hint: this
 *   compressed loss beats the paper's L1 on f clearly (median lobe error 4.6 %
 *   vs 8.1 %, worst 217 % for plain L1).
 * - MODEL_LOSS_L1: |f̂(o) − f| with f̂ = o (MODEL_OUTPUT_F) or exp(o) − 1
 *   (MODEL_OUTPUT_LOG1P, o clamped at 80): the paper's loss.
 *
 * Neither clamps f̂ at 0 the way inference does: the clamp has no gradient. */
#ifndef NBRDF_MODEL_LOSS_H
#define NBRDF_MODEL_LOSS_H

#include <stddef.h>

#include "model/decoder.h"

typedef enum model_loss_kind { MODEL_LOSS_L1_LOG1P = 0, MODEL_LOSS_L1 = 1 } model_loss_kind;

/* "l1-log1p" / "l1"; parse returns 0 for an unknown name. */
const char *model_loss_name(model_loss_kind kind);
int model_loss_parse(const char *name, model_loss_kind *kind);

/* Sum over n rows of w_r · loss_r (w NULL: all weights 1); if dloss_do is
 * non-NULL it receives scale · w_r · ∂loss_r/∂o_r per row (scale = 1/N for a
 * mean over N rows). */
double model_loss_sum(model_loss_kind kind, model_output output, size_t n, const float *o,
                      const float *f, const float *w, float scale, float *dloss_do);

#endif
