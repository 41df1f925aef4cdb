/* Private layout of networks and workspaces, shared by the files of src/nn. */
#ifndef NBRDF_NN_INTERNAL_H
#define NBRDF_NN_INTERNAL_H

#include <stddef.h>

#include "nn/nn.h"

/* The element-wise hot loops of src/nn (kernels.c, adam.c): AVX-512 and AVX2 clones picked at
 * run time, the CPU's full vector width. Every lane computes the same IEEE operations (no
 * contraction), so the results are identical bit for bit on every path. Those files also
 * build with -O3 (a pragma) and -fno-math-errno (src/CMakeLists.txt: a pragma cannot lift
 * errno, and sqrtf that may set it stays scalar). */
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__)
#define NN_HOT __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define NN_HOT
#endif

#define NN_NONE ((size_t)-1)
/* Every buffer starts on a cache line, so that rows of 16 floats stay aligned for SIMD. */
#define NN_ALIGN 64

/* A layer resolved against its input width, with the offsets (in floats) of its tensors in the
 * parameter array; NN_NONE where the layer has no such tensor. PLAIN uses the "1" slots
 * (fc, norm); LINEAR uses w1/b1; LAYERNORM g1/be1; RESIDUAL both slots. */
typedef struct nn_layer {
  nn_kind kind;
  int in, out, hidden;
  int skip_from;  /* activation index, -1 = none */
  int skip_width; /* width of that activation */
  size_t w1, b1, g1, be1;
  size_t w2, b2, g2, be2;
  size_t wskip; /* projection of the skip, NN_NONE for an identity skip */
} nn_layer;

struct nn_network {
  nn_spec spec;
  nn_layer layers[NBRDF_NN_MAX_LAYERS];
  int widths[NBRDF_NN_MAX_LAYERS + 1];      /* width of each activation */
  int skip_source[NBRDF_NN_MAX_LAYERS + 1]; /* non-zero: some later layer reads it */
  int max_width;                            /* over activations and hidden widths */
  float *params;
  size_t n_params;
  nn_tensor *tensors;
  int n_tensors;
};

/* Resolves spec (already validated) into layers, widths and tensors. Sets nn->n_params and
 * fills nn->tensors when it is non-NULL (count them first with tensors == NULL). */
void nn_resolve(nn_network *nn);

/* Pointers of one layer's buffers during forward (TRAIN: the stored ones, INFER: scratch). */
typedef struct nn_layer_buffers {
  float *z1, *r1, *h; /* pre-norm / x-hat, 1/sigma per row, and post-ReLU of the first norm */
  float *z2, *r2;     /* the same for a residual block's second norm */
} nn_layer_buffers;

struct nn_workspace {
  nn_spec spec; /* the architecture it was sized for */
  nn_mode mode;
  int max_batch;
  int rows;      /* rows its buffers hold: max_batch (TRAIN), at most nn_infer_block (INFER) */
  int batch;     /* rows of the last TRAIN forward */
  int has_fresh; /* a TRAIN forward is waiting for its backward */
  void *block;   /* one allocation holding everything below */
  size_t bytes;
  float *act[NBRDF_NN_MAX_LAYERS + 1]; /* TRAIN: all; INFER: skip sources (0 = caller's) */
  nn_layer_buffers layer[NBRDF_NN_MAX_LAYERS];
  /* INFER */
  float *pingpong[2], *scratch_z, *scratch_h, *scratch_z2, *scratch_r;
  /* TRAIN, backward */
  float *grad_chain[2], *grad_hidden, *grad_skip[NBRDF_NN_MAX_LAYERS + 1];
  double *acc; /* 4 * max_width column sums over the batch */
};

/* Rows an inference pass processes at a time: each activation buffer stays around 2 MiB, so
 * that a layer's output is still in cache for the next. Larger blocks were up to 3x slower on
 * the 2-core build machine for widths 128..512 (16384 vs 1024..4096 rows); smaller ones gain
 * nothing and make the GEMMs less efficient. */
int nn_infer_block(const nn_network *nn);

/* Do two valid specs describe the same architecture (same buffers, same tensors)? */
int nn_same_spec(const nn_spec *a, const nn_spec *b);

/* Layer kernels over rows x w buffers (src/nn/kernels.c). */
void nn_gemm_xwt(int rows, int in, int out, const float *x, const float *w, float beta, float *y);
/* dx = g W for W [out x in]; beta = 1 adds to dx. */
void nn_gemm_gw(int rows, int out, int in, const float *g, const float *w, float beta, float *dx);
/* dW += g^T x. */
void nn_gemm_gtx(int rows, int out, int in, const float *g, const float *x, float *dw);
void nn_ln_forward(int rows, int w, float *u, const float *bias, const float *add1,
                   const float *add2, const float *gamma, const float *beta, float *rstd, float *y,
                   int relu);
void nn_ln_backward(int rows, int w, float *g, const float *y_relu, const float *xhat,
                    const float *rstd, const float *gamma, double *dgamma, double *dbeta,
                    double *dbias);
void nn_add_rows(int rows, int w, float *y, const float *bias, const float *add);
void nn_relu_forward(size_t n, const float *x, float *y);
void nn_relu_backward(size_t n, float *g, const float *y);
void nn_colsum(int rows, int w, const float *g, double *acc);
void nn_flush(int w, double *acc, float *grad);

#endif
