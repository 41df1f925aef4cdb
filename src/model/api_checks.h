/* The argument checks and batch size of the public calls of
 * include/nbrdf/model.h, shared by model_api.c and the one public call defined
 * above this layer (nbrdf_model_project, src/train/project_api.c: its fit runs
 * in the trainer), so that every call checks its arguments and sizes its
 * batches the same way. Failures are NBRDF_ERR_ARGUMENT with a message naming
 * the query or value. */
#ifndef NBRDF_MODEL_API_CHECKS_H
#define NBRDF_MODEL_API_CHECKS_H

#include <stddef.h>

#include "nbrdf/status.h"

/* Rows per network batch of a public call (the scratch it allocates is bounded). */
#define MODEL_API_BATCH 4096

/* wi, wo [n × 3]: finite unit vectors above the horizon (z > 0). */
nbrdf_status model_check_directions(size_t n, const float *wi, const float *wo, nbrdf_error *err);
/* x [count]: all finite; `what` starts the message. */
nbrdf_status model_check_finite(const float *x, size_t count, const char *what, nbrdf_error *err);
/* The batch for `rows` rows: min(rows, MODEL_API_BATCH), at least `multiple`. */
int model_batch_for(size_t rows, int multiple);

#endif
