/* Dense networks with forward and backward passes on CBLAS, and Adam.
 *
 * The building blocks of the paper's networks (Fan et al. 2022, Fig. 3): Linear, LayerNorm
 * with learned scale and shift, ReLU, the bottleneck residual block, the "plain" layer, and
 * additive skip connections added before normalisation and activation. A network knows
 * nothing about BRDFs; losses, encodings and latents live in src/model.
 *
 * Conventions
 * - Activations are float32, row-major [batch x features]: row r of a buffer is one query.
 * - A Linear layer computes y = x W^T + b with W stored row-major [out x in] (the PyTorch
 *   nn.Linear layout, so weights trained there load as they are). The forward GEMM is
 *   cblas_sgemm(RowMajor, NoTrans, Trans); OpenBLAS packs both operands, so this costs the
 *   same as NoTrans/NoTrans (bench_nn --threads: 104.7 vs 105.4 GFLOP/s at 4096x256x256,
 *   within 1 % at the other decoder shapes). Backward: dL/dx = G W (NoTrans, NoTrans) and
 *   dL/dW += G^T x (Trans, NoTrans), G = dL/dy.
 * - All parameters of a network live in ONE contiguous float array (nn_params); each
 *   tensor is a named view into it (nn_tensor). Gradients use the same layout in a
 *   caller-owned array of nn_param_count floats, so that several threads can each
 *   accumulate their own gradients against one shared network.
 * - A network is read-only during forward/backward; a workspace (one per thread) holds every
 *   activation the backward pass needs, allocated once for a maximum batch size. Forward and
 *   backward allocate nothing.
 *
 * Block definitions (w = block width, x = block input, s = skip term, see below):
 *   LINEAR     y = x W^T + b (+ s)                                   in -> width
 *   LAYERNORM  y = (x - mean) / sqrt(var + 1e-5) * gamma + beta      (per row, biased var)
 *   RELU       y = max(x, 0)
 *   PLAIN      y = ReLU(LN(x W^T + b + s))                           in -> width
 *   RESIDUAL   h = ReLU(LN1(x W1^T + b1))                            w -> hidden (default w/2)
 *              y = ReLU(LN2(h W2^T + b2 + x + s))                    hidden -> w
 * i.e. the residual and any skip term are added before normalisation and activation
 * (paper Fig. 3), and a RESIDUAL block's input and output widths are equal.
 *
 * Skip connections: layer i may add an earlier activation a_j (j = 0: the network input,
 * j = k >= 1: the output of layer k-1; j <= i) to its pre-normalisation sum. If a_j's width
 * differs from the layer's width, the skip goes through a learned projection without bias
 * (s = a_j P^T, P [width x width_j], tensor "layers.<i>.skip.weight"); otherwise s = a_j.
 * LAYERNORM and RELU layers take no skip.
 *
 * Tensor names (PyTorch-like, <i> = index in the layer list):
 *   LINEAR     layers.<i>.weight [out x in], layers.<i>.bias [out]
 *   LAYERNORM  layers.<i>.weight [w] (gamma), layers.<i>.bias [w] (beta)
 *   PLAIN      layers.<i>.fc.weight, .fc.bias, .norm.weight, .norm.bias
 *   RESIDUAL   layers.<i>.fc1.weight, .fc1.bias, .norm1.weight, .norm1.bias,
 *              layers.<i>.fc2.weight, .fc2.bias, .norm2.weight, .norm2.bias
 *   any        layers.<i>.skip.weight (only when a projected skip is present)
 * Tensors appear in the parameter array in this order, layer by layer.
 *
 * Initialisation (nn_init_params, deterministic for a seed and independent of the
 * thread count): a weight feeding a ReLU (PLAIN fc, RESIDUAL fc1 and fc2, a LINEAR followed
 * by RELU or LAYERNORM) is He/Kaiming uniform U(-sqrt(6/fan_in), +sqrt(6/fan_in)); any other
 * weight (an output LINEAR, a skip projection) is LeCun uniform U(-sqrt(3/fan_in), ..);
 * biases 0; LayerNorm gamma 1, beta 0. Each tensor draws from its own PCG32 stream
 * (stream = tensor index), so appending a layer does not change the earlier ones' values.
 *
 * Threading: the GEMMs use OpenBLAS's own threads; the element-wise passes (bias, residual,
 * LayerNorm, ReLU: vectorised, AVX2 picked at run time) run on the calling thread. This layer
 * never calls openblas_set_num_threads (it is process-global: one library cannot know what
 * the rest of the process wants). Measured with `bench_nn --threads` on the 2-core build
 * machine, whose Debian OpenBLAS is the pthreads variant (libopenblas-dev pulls in
 * libopenblas0-pthread 0.3.21; libopenblas0-openmp exists in bookworm but would replace the
 * system-wide libblas alternative for everyone, so it was not tried):
 * - two OpenMP threads each calling sgemm on half the batch were slower than one caller, much
 *   slower at small batches (paper decoder, batch 64: 5.3k vs 35k queries/s), whether
 *   OpenBLAS kept 2 threads or was set to 1;
 * - OpenMP in the element-wise passes made whole networks 3-50x slower with the default
 *   OMP_WAIT_POLICY (libgomp's and OpenBLAS's idle threads spin against each other on 2
 *   cores) and was no faster with OMP_WAIT_POLICY=passive. So there is no OpenMP here;
 * - with the other engineers' jobs on the cores, OPENBLAS_NUM_THREADS=1 was as fast as 2 or
 *   faster (25k decoder at 4096: 1.2M vs 0.35M queries/s in one run, equal in another): the
 *   choice is the process's, through the environment, not this library's.
 * Callers should therefore hand large batches to one thread rather than split them across
 * OpenMP threads. Different workspaces on one network may still be used from different
 * threads at the same time (tested). Results are deterministic: the same call gives the same
 * bits for a given OpenBLAS thread count; changing OPENBLAS_NUM_THREADS (1 vs 2) changes the
 * GEMMs' rounding in the last bits (measured), so bit-exact comparisons across machines or
 * settings need a tolerance. */
#ifndef NBRDF_NN_NN_H
#define NBRDF_NN_NN_H

#include <stddef.h>
#include <stdint.h>

#include "nbrdf/status.h"

/* ---------------------------------------------------------------- spec (architecture) -- */

typedef enum nn_kind {
  NBRDF_NN_LINEAR = 1,
  NBRDF_NN_LAYERNORM,
  NBRDF_NN_RELU,
  NBRDF_NN_PLAIN,
  NBRDF_NN_RESIDUAL
} nn_kind;

typedef struct nn_layer_spec {
  nn_kind kind;
  int width;     /* output width (LINEAR, PLAIN); for the others 0 or the input width */
  int hidden;    /* RESIDUAL bottleneck width; 0 = width / 2 */
  int has_skip;  /* non-zero: add activation `skip_from` before normalisation */
  int skip_from; /* 0 = network input, k >= 1 = output of layer k-1; must be <= own index */
} nn_layer_spec;

#define NBRDF_NN_MAX_LAYERS 64
#define NBRDF_NN_MAX_WIDTH 8192

/* The architecture: a plain value (copyable, no pointers). The output width is the last
 * layer's width. Serialises to JSON (nn_spec_to_json) for safetensors __metadata__. */
typedef struct nn_spec {
  int n_inputs;
  int n_layers;
  nn_layer_spec layers[NBRDF_NN_MAX_LAYERS];
} nn_spec;

/* Empty spec with `n_inputs` input features. */
void nn_spec_init(nn_spec *spec, int n_inputs);
/* Appends a layer; `width` is ignored (may be 0) for LAYERNORM, RELU and RESIDUAL, whose
 * width equals their input's. Returns the new layer's index, or -1 when the spec is full
 * (nn_spec_validate then reports it). */
int nn_spec_add(nn_spec *spec, nn_kind kind, int width);
/* Sets layer `layer`'s skip source (0 = network input, k >= 1 = output of layer k-1). */
void nn_spec_skip(nn_spec *spec, int layer, int from);
/* The residual MLP of the paper: PLAIN(n_inputs -> width), then n_blocks times
 * [RESIDUAL(width), and PLAIN(width -> width) if interleave_plain], then LINEAR(width ->
 * n_outputs). The released decoder is (38, 256, 8, 1, 1): 1,058,560 multiply-adds. */
nbrdf_status nn_spec_resmlp(nn_spec *spec, int n_inputs, int width, int n_blocks,
                            int interleave_plain, int n_outputs, nbrdf_error *err);

/* Checks kinds, widths (1..NBRDF_NN_MAX_WIDTH, LayerNorm >= 2, even RESIDUAL hidden > 0)
 * and skip sources; the message names the layer ("layer 3 (residual): ..."). */
nbrdf_status nn_spec_validate(const nn_spec *spec, nbrdf_error *err);
/* Width of activation j (0 = input, k = output of layer k-1) of a VALID spec. */
int nn_spec_width(const nn_spec *spec, int activation);
int nn_spec_outputs(const nn_spec *spec);
/* Multiply-adds of the GEMMs per query (what the paper counts). */
int64_t nn_spec_macs(const nn_spec *spec);
size_t nn_spec_param_count(const nn_spec *spec);
/* "linear", "layernorm", "relu", "plain", "residual"; NULL for an unknown kind. */
const char *nn_kind_name(nn_kind kind);

/* JSON form, e.g.
 *   {"format":"nbrdf-nn","version":1,"inputs":38,"layers":[{"kind":"plain","width":256},
 *    {"kind":"residual","hidden":128},{"kind":"linear","width":1,"skip":0}]}
 * ("skip" present only when has_skip). *json receives a malloc'd, NUL-terminated compact
 * string that the caller frees with free(). */
nbrdf_status nn_spec_to_json(const nn_spec *spec, char **json, nbrdf_error *err);
/* Parses and validates; unknown keys, wrong types and invalid architectures are refused with
 * a message naming the offending layer/key. `spec` is untouched on failure. */
nbrdf_status nn_spec_from_json(const char *json, nn_spec *spec, nbrdf_error *err);

/* ---------------------------------------------------------------------- the network -- */

typedef struct nn_network nn_network;

/* A named view into the parameter (and gradient) array: a weight is [rows = out, cols = in]
 * row-major; a vector has rank 1, rows = length, cols = 1. */
typedef struct nn_tensor {
  char name[48];
  size_t offset; /* in floats, from the start of the parameter array */
  size_t count;  /* rows * cols */
  int rank;      /* 2 for weights, 1 for biases and LayerNorm gamma/beta */
  int rows, cols;
} nn_tensor;

/* Validates the spec and allocates the parameters, zero-filled (call init_params or load
 * weights before use). */
nbrdf_status nn_create(const nn_spec *spec, nn_network **out, nbrdf_error *err);
void nn_destroy(nn_network *nn);

const nn_spec *nn_get_spec(const nn_network *nn);
int nn_inputs(const nn_network *nn);
int nn_outputs(const nn_network *nn);

/* The contiguous parameter array (64-byte aligned) and its length in floats. */
float *nn_params(nn_network *nn);
const float *nn_params_const(const nn_network *nn);
size_t nn_param_count(const nn_network *nn);

int nn_tensor_count(const nn_network *nn);
const nn_tensor *nn_tensor_at(const nn_network *nn, int index);
/* NULL when no tensor has that name. */
const nn_tensor *nn_find_tensor(const nn_network *nn, const char *name);

/* Deterministic initialisation (see the top of this file). */
void nn_init_params(nn_network *nn, uint64_t seed);

/* ----------------------------------------------------------------------- workspaces -- */

typedef enum nn_mode {
  NBRDF_NN_TRAIN = 0, /* keeps every activation: forward then backward */
  NBRDF_NN_INFER = 1  /* forward only, any batch: processed in cache-sized blocks of at most
                         max_batch rows through ping-pong buffers */
} nn_mode;

typedef struct nn_workspace nn_workspace;

/* A workspace for batches of up to `max_batch` rows of this network's architecture (it may be
 * used with any network of an identical spec). */
nbrdf_status nn_workspace_create(const nn_network *nn, int max_batch, nn_mode mode,
                                 nn_workspace **out, nbrdf_error *err);
void nn_workspace_destroy(nn_workspace *ws);
int nn_workspace_max_batch(const nn_workspace *ws);
/* Bytes a workspace for this spec, batch and mode allocates. */
size_t nn_workspace_bytes(const nn_spec *spec, int max_batch, nn_mode mode);

/* ----------------------------------------------------------------- forward / backward -- */

/* y[batch x outputs] = network(x[batch x inputs]). In TRAIN mode batch <= max_batch and the
 * workspace keeps what backward needs (x is copied; the caller may reuse it). In INFER mode
 * any batch >= 1 is processed in blocks of min(max_batch, ~2 MiB per activation buffer)
 * rows, so an INFER workspace never holds more than that. `y` must not overlap `x`.
 * Non-finite inputs are not checked here (hot path); they propagate. */
nbrdf_status nn_forward(const nn_network *nn, nn_workspace *ws, const float *x, int batch, float *y,
                        nbrdf_error *err);

/* Backward pass of the LAST forward on `ws` (TRAIN mode), with dy = dL/dy [batch x outputs]:
 * - dx: if non-NULL, receives dL/dx [batch x inputs] (overwritten), e.g. for a latent that
 *   is part of the input;
 * - grad: if non-NULL, dL/dparams is ADDED into it (same layout as nn_params; zero it
 *   before the first batch of a step). With grad == NULL the weight-gradient GEMMs are
 *   skipped (a frozen network, as in projection).
 * The stored activations are consumed: call forward again before another backward. */
nbrdf_status nn_backward(const nn_network *nn, nn_workspace *ws, const float *dy, float *dx,
                         float *grad, nbrdf_error *err);

/* -------------------------------------------------------------------------------- Adam -- */

/* Adam (Kingma & Ba 2015) with decoupled weight decay (AdamW, Loshchilov & Hutter 2019) and
 * the paper's step decay: lr(t) = lr * gamma^floor(t / decay_every), t = steps taken. */
typedef struct nn_adam_options {
  float lr;           /* base learning rate of the default group */
  float beta1, beta2; /* moment decay rates, in [0, 1) */
  float eps;          /* added to sqrt(v_hat) */
  float weight_decay; /* decoupled: p -= lr(t) * weight_decay * p; 0 = none */
  int decay_every;    /* steps between learning-rate decays; 0 = never */
  float decay_gamma;  /* factor per decay, in (0, 1] */
} nn_adam_options;

#define NBRDF_ADAM_OPTIONS_DEFAULT                                                                 \
  { 1e-3f, 0.9f, 0.999f, 1e-8f, 0.0f, 0, 1.0f }

typedef struct nn_adam nn_adam;

/* An optimiser for a float array of `n` parameters (a network's nn_params, or any
 * external array such as a latent table). Moments start at zero. */
nbrdf_status nn_adam_create(size_t n, const nn_adam_options *opts, nn_adam **out, nbrdf_error *err);
void nn_adam_destroy(nn_adam *adam);

/* Gives parameters [offset, offset + count) their own base learning rate and weight decay
 * (a parameter group). Later groups override earlier ones where they overlap; parameters in
 * no group use the options' lr and weight_decay. Returns the group's id (>= 1) in *group. */
nbrdf_status nn_adam_add_group(nn_adam *adam, size_t offset, size_t count, float lr,
                               float weight_decay, int *group, nbrdf_error *err);
/* Same, for every tensor of `nn` whose name contains `name_part` (e.g. ".weight", "norm");
 * fails if none matches. */
nbrdf_status nn_adam_add_group_tensors(nn_adam *adam, const nn_network *nn, const char *name_part,
                                       float lr, float weight_decay, int *group, nbrdf_error *err);

/* One step on all n parameters: params -= lr(t) * m_hat / (sqrt(v_hat) + eps) (+ decay).
 * Non-finite gradients are refused (nothing is updated) with the index of the first one. */
nbrdf_status nn_adam_step(nn_adam *adam, float *params, const float *grads, nbrdf_error *err);
/* Learning rate the NEXT step will use for `group` (0 = default). */
float nn_adam_lr(const nn_adam *adam, int group);
/* Steps taken so far. */
int64_t nn_adam_steps(const nn_adam *adam);
/* Forgets moments and step count (e.g. to reuse one optimiser for a new projection). */
void nn_adam_reset(nn_adam *adam);
/* The moment arrays (n floats each) and the step count, for checkpoints: a training run
 * resumed from saved moments and steps continues exactly as if it had not stopped. */
float *nn_adam_moment(nn_adam *adam, int second); /* 0: m, 1: v */
size_t nn_adam_size(const nn_adam *adam);
void nn_adam_set_steps(nn_adam *adam, int64_t steps);

#endif
