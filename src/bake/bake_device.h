/* The device a bake's networks run on (nbrdf_bake_options.device; docs/GPU.md). */
#ifndef NBRDF_BAKE_BAKE_DEVICE_H
#define NBRDF_BAKE_BAKE_DEVICE_H

#include "model/model_gpu.h"
#include "nbrdf/bake.h"

/* CPU: *out = NULL. AUTO / GPU: uploads the layering and sampling networks of `model` and,
 * when the energy audit is on, the decoder of `audit_model` (model_gpu_open), and tells
 * o->note where the networks run. GPU without a GPU: the error says why. */
nbrdf_status bake_device_open(const nbrdf_model *model, const nbrdf_model *audit_model,
                              const nbrdf_bake_options *o, model_gpu **out, nbrdf_error *err);

#endif
