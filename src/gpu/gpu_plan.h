/* A network's forward pass as a list of GPU steps over numbered buffers (no Vulkan here):
 * which buffer holds each activation (ping-pong, skip sources kept, as src/nn/forward.c's
 * inference), and per linear map a GEMM step with its fused epilogue, then a row step
 * (LayerNorm + ReLU) where the layer has one. */
#ifndef NBRDF_GPU_GPU_PLAN_H
#define NBRDF_GPU_GPU_PLAN_H

#include <stdint.h>

#include "nn/nn.h"

/* The kernels' push constants (kernels/nn_gemm.comp, nn_rownorm.comp, nn_gemm_coop.comp):
 * rows, K (inputs), N (outputs / row width), offsets into the parameter array in floats. */
typedef struct gpu_push {
  uint32_t rows, K, N, w_off, b_off, flags, g_off, be_off;
} gpu_push;

enum {
  GPU_ACCUMULATE = 1u, /* y = previous y + x W^T */
  GPU_ADD1 = 2u,       /* + a1 (a residual block's input) */
  GPU_ADD2 = 4u,       /* + a2 (an identity skip) */
  GPU_BIAS = 8u,
  GPU_NORM = 16u, /* row step: LayerNorm */
  GPU_RELU = 32u  /* row step: ReLU */
};

typedef enum gpu_step_kind { GPU_STEP_GEMM = 0, GPU_STEP_ROWNORM, GPU_STEP_COPY } gpu_step_kind;

typedef struct gpu_step {
  gpu_step_kind kind;
  int x, y, a1, a2; /* buffer indices; -1 = none (x of a row step: none, it works in place) */
  gpu_push push;    /* rows filled at record time; COPY copies push.N floats per row */
} gpu_step;

#define GPU_PLAN_MAX_STEPS (4 * NBRDF_NN_MAX_LAYERS + 8)
#define GPU_PLAN_MAX_BUFFERS (NBRDF_NN_MAX_LAYERS + 6)

typedef struct gpu_plan {
  int n_steps, n_buffers;
  gpu_step steps[GPU_PLAN_MAX_STEPS];
  int buffer_width[GPU_PLAN_MAX_BUFFERS]; /* floats per row */
  int input, output;                      /* buffers of the network's input and output */
  int floats_per_row;                     /* sum of buffer widths */
  int max_width;
} gpu_plan;

nbrdf_status gpu_plan_make(const nn_network *nn, gpu_plan *plan, nbrdf_error *err);

#endif
