/* Throughput of the dense networks of src/nn against the machine's own cblas_sgemm rate on
 * exactly the GEMM calls the network makes (same shapes, same weights, same order), measured
 * in the same run. Prints markdown tables.
 *
 *   bench_nn            decoders (paper 256x(8+8), ~100k, ~25k, ~5k MACs) and the layering
 *                       network at batches 1, 16, 256, 4096, 65536
 *   bench_nn --quick    batches 16 and 4096 only
 *   bench_nn --threads  OpenBLAS variant, threads vs OpenMP callers, GEMM orientation
 *
 * "fraction" = time of the GEMM-only replay / time of the network: the share of the machine's
 * GEMM rate that the whole network reaches (1.0 = no overhead outside the GEMMs). Times are
 * the fastest call of three interleaved rounds (network, replay, network, replay, ...). */
#include <cblas.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "nn/internal.h"
#include "nn/nn.h"

#include "bench_clock.h"
#include "bench_kernels.h"

#define ROUNDS 3                     /* interleaved rounds of network and replay timings */
#define TRAIN_BYTES_CAP (1ull << 30) /* training workspaces stay under 1 GiB; chunk beyond */

typedef void (*work_fn)(void *ctx);

/* Seconds per call: the fastest of the calls made in at least `min_s` (at least 2 calls).
 * The minimum, not the mean, because other jobs share the 2 cores: it is the figure least
 * disturbed by them, for the network and its GEMM replay alike. */
static double time_calls(work_fn fn, void *ctx, double min_s) {
  double best = 1e30, start = bench_wall_seconds();
  int n = 0;
  do {
    double t0 = bench_wall_seconds();
    fn(ctx);
    double t = bench_wall_seconds() - t0;
    if (t < best) best = t;
    n++;
  } while (n < 2 || bench_wall_seconds() - start < min_s);
  return best;
}

typedef struct run {
  nn_network *nn;
  nn_workspace *ws;
  int batch, chunk;
  float *x, *y, *dy, *grad;
  float *a, *b; /* replay buffers */
} run;

static void die(nbrdf_status st, const nbrdf_error *err) {
  if (st == NBRDF_OK) return;
  fprintf(stderr, "bench_nn: %s\n", err->message);
  exit(1);
}

static void net_forward(void *ctx) {
  run *r = ctx;
  nbrdf_error err;
  die(nn_forward(r->nn, r->ws, r->x, r->batch, r->y, &err), &err);
}

static void net_train(void *ctx) {
  run *r = ctx;
  nbrdf_error err;
  int in = nn_inputs(r->nn), out = nn_outputs(r->nn);
  for (int done = 0; done < r->batch; done += r->chunk) {
    die(nn_forward(r->nn, r->ws, r->x + (size_t)done * in, r->chunk, r->y + (size_t)done * out,
                   &err),
        &err);
    die(nn_backward(r->nn, r->ws, r->dy + (size_t)done * out, NULL, r->grad, &err), &err);
  }
}

/* The GEMMs of one forward pass on `rows` rows (nn_gemm_xwt: sgemv for a single row). */
static void replay_forward_rows(run *r, int rows) {
  const nn_network *nn = r->nn;
  const float *p = nn->params;
  for (int i = 0; i < nn->spec.n_layers; i++) {
    const nn_layer *l = &nn->layers[i];
    if (l->wskip != NN_NONE) nn_gemm_xwt(rows, l->skip_width, l->out, r->a, p + l->wskip, 0, r->b);
    if (l->kind == NBRDF_NN_LINEAR || l->kind == NBRDF_NN_PLAIN)
      nn_gemm_xwt(rows, l->in, l->out, r->a, p + l->w1, l->wskip != NN_NONE, r->b);
    if (l->kind == NBRDF_NN_RESIDUAL) {
      nn_gemm_xwt(rows, l->in, l->hidden, r->a, p + l->w1, 0, r->b);
      nn_gemm_xwt(rows, l->hidden, l->out, r->b, p + l->w2, 0, r->a);
    }
  }
}

/* The GEMMs of nn_backward(dx = NULL, grad != NULL). */
static void replay_backward_rows(run *r, int rows) {
  const nn_network *nn = r->nn;
  const float *p = nn->params;
  for (int i = nn->spec.n_layers - 1; i >= 0; i--) {
    const nn_layer *l = &nn->layers[i];
    if (l->kind == NBRDF_NN_LINEAR || l->kind == NBRDF_NN_PLAIN) {
      nn_gemm_gtx(rows, l->out, l->in, r->a, r->b, r->grad + l->w1);
      if (i > 0) nn_gemm_gw(rows, l->out, l->in, r->a, p + l->w1, 0, r->b);
    }
    if (l->kind == NBRDF_NN_RESIDUAL) {
      nn_gemm_gtx(rows, l->out, l->hidden, r->a, r->b, r->grad + l->w2);
      nn_gemm_gw(rows, l->out, l->hidden, r->a, p + l->w2, 0, r->b);
      nn_gemm_gtx(rows, l->hidden, l->in, r->b, r->a, r->grad + l->w1);
      if (i > 0) nn_gemm_gw(rows, l->hidden, l->in, r->b, p + l->w1, 1, r->a);
    }
    if (l->wskip != NN_NONE) {
      nn_gemm_gtx(rows, l->out, l->skip_width, r->a, r->b, r->grad + l->wskip);
      if (l->skip_from > 0) nn_gemm_gw(rows, l->out, l->skip_width, r->a, p + l->wskip, 1, r->b);
    }
  }
}

static void replay_forward(void *ctx) {
  run *r = ctx;
  for (int done = 0; done < r->batch; done += r->chunk)
    replay_forward_rows(r, r->batch - done < r->chunk ? r->batch - done : r->chunk);
}

static void replay_train(void *ctx) {
  run *r = ctx;
  for (int done = 0; done < r->batch; done += r->chunk) {
    replay_forward_rows(r, r->chunk);
    replay_backward_rows(r, r->chunk);
  }
}

/* Multiply-adds of the backward GEMMs with dx == NULL: weights' and inputs' gradients, minus
 * the first layer's input gradient. */
static double backward_macs(const nn_network *nn) {
  double m = 2.0 * (double)nn_spec_macs(&nn->spec);
  const nn_layer *l0 = &nn->layers[0];
  if (l0->kind == NBRDF_NN_LINEAR || l0->kind == NBRDF_NN_PLAIN) m -= (double)l0->in * l0->out;
  if (l0->kind == NBRDF_NN_RESIDUAL) m -= (double)l0->in * l0->hidden;
  return m;
}

static void fmt_bytes(char *s, size_t n, double b) {
  if (b >= 1 << 30)
    snprintf(s, n, "%.2f GiB", b / (1 << 30));
  else if (b >= 1 << 20)
    snprintf(s, n, "%.1f MiB", b / (1 << 20));
  else
    snprintf(s, n, "%.0f KiB", b / 1024);
}

static void bench_network(const char *name, const nn_spec *spec, const int *batches, int n_batches,
                          double min_s) {
  nbrdf_error err;
  nn_network *nn = NULL;
  die(nn_create(spec, &nn, &err), &err);
  nn_init_params(nn, 1);
  const int in = nn_inputs(nn), out = nn_outputs(nn);
  const double macs = (double)nn_spec_macs(spec), bmacs = backward_macs(nn);
  int max_b = batches[n_batches - 1];
  run r = {nn, NULL, 0, 0, NULL, NULL, NULL, NULL, NULL, NULL};
  r.x = malloc(sizeof(float) * (size_t)max_b * in);
  r.y = malloc(sizeof(float) * (size_t)max_b * out);
  r.dy = malloc(sizeof(float) * (size_t)max_b * out);
  r.grad = calloc(nn_param_count(nn), sizeof(float));
  const int block = nn_infer_block(nn); /* rows per inference block, replayed the same way */
  size_t rb = sizeof(float) * (size_t)(max_b < block ? max_b : block) * nn->max_width;
  size_t train_cap = 1;
  while (train_cap * 2 <= (size_t)max_b &&
         nn_workspace_bytes(spec, (int)train_cap * 2, NBRDF_NN_TRAIN) <= TRAIN_BYTES_CAP)
    train_cap *= 2;
  if (train_cap * nn->max_width * sizeof(float) > rb)
    rb = train_cap * nn->max_width * sizeof(float);
  r.a = calloc(1, rb);
  r.b = calloc(1, rb);
  for (size_t i = 0; i < (size_t)max_b * in; i++)
    r.x[i] = (float)((i * 2654435761u) % 1000) / 500 - 1;
  for (size_t i = 0; i < (size_t)max_b * out; i++)
    r.dy[i] = 1e-3f;
  for (int k = 0; k < n_batches; k++) {
    int B = batches[k];
    char mem_f[32], mem_t[32];
    /* forward: inference workspace, which works in blocks of nn_infer_block rows */
    r.batch = B;
    r.chunk = B < block ? B : block;
    die(nn_workspace_create(nn, B, NBRDF_NN_INFER, &r.ws, &err), &err);
    fmt_bytes(mem_f, sizeof mem_f, (double)nn_workspace_bytes(spec, r.chunk, NBRDF_NN_INFER));
    double tn = 1e30, tg = 1e30;
    for (int round = 0; round < ROUNDS; round++) {
      tn = fmin(tn, time_calls(net_forward, &r, min_s));
      tg = fmin(tg, time_calls(replay_forward, &r, min_s));
    }
    nn_workspace_destroy(r.ws);
    double fq = B / tn, f_gflops = 2 * macs * B / tn / 1e9, g_gflops = 2 * macs * B / tg / 1e9;
    /* forward + backward: training workspace, gradients accumulated over chunks */
    r.chunk = B < (int)train_cap ? B : (int)train_cap;
    die(nn_workspace_create(nn, r.chunk, NBRDF_NN_TRAIN, &r.ws, &err), &err);
    fmt_bytes(mem_t, sizeof mem_t, (double)nn_workspace_bytes(spec, r.chunk, NBRDF_NN_TRAIN));
    double un = 1e30, ug = 1e30;
    for (int round = 0; round < ROUNDS; round++) {
      un = fmin(un, time_calls(net_train, &r, min_s));
      ug = fmin(ug, time_calls(replay_train, &r, min_s));
    }
    nn_workspace_destroy(r.ws);
    double tq = B / un, t_gflops = 2 * (macs + bmacs) * B / un / 1e9;
    double tg_gflops = 2 * (macs + bmacs) * B / ug / 1e9;
    printf(
        "| %s | %.0f | %d | %.4g | %.1f | %.1f | %.2f | %s | %.4g | %.1f | %.1f | %.2f | %s%s |\n",
        name, macs, B, fq, f_gflops, g_gflops, tg / tn, mem_f, tq, t_gflops, tg_gflops, ug / un,
        mem_t, r.chunk < B ? " (chunks)" : "");
    fflush(stdout);
  }
  free(r.x);
  free(r.y);
  free(r.dy);
  free(r.grad);
  free(r.a);
  free(r.b);
  nn_destroy(nn);
}

/* ---- threading and orientation study ---- */

typedef struct par {
  nn_network *nn;
  nn_workspace *ws[2];
  float *x, *y;
  int batch;
  int callers;
} par;

static void par_forward(void *ctx) {
  par *p = ctx;
  int in = nn_inputs(p->nn);
  if (p->callers == 1) {
    nbrdf_error err;
    die(nn_forward(p->nn, p->ws[0], p->x, p->batch, p->y, &err), &err);
    return;
  }
  int half = p->batch / 2;
#pragma omp parallel num_threads(2)
  {
    int t = omp_get_thread_num();
    nbrdf_error err;
    die(nn_forward(p->nn, p->ws[t], p->x + (size_t)t * half * in, half,
                   p->y + (size_t)t * half * nn_outputs(p->nn), &err),
        &err);
  }
}

typedef struct gemm_case {
  int m, n, k;
  CBLAS_TRANSPOSE tb;
  float *a, *b, *c;
} gemm_case;

static void one_gemm(void *ctx) {
  gemm_case *g = ctx;
  cblas_sgemm(CblasRowMajor, CblasNoTrans, g->tb, g->m, g->n, g->k, 1.0f, g->a, g->k, g->b,
              g->tb == CblasTrans ? g->k : g->n, 0.0f, g->c, g->n);
}

static void threads_study(double min_s) {
  static const char *par_names[] = {"sequential", "pthreads", "OpenMP"};
  int par_kind = openblas_get_parallel();
  int blas_threads = openblas_get_num_threads();
  printf("OpenBLAS: %s; threading: %s; openblas_get_num_threads() = %d; "
         "omp_get_max_threads() = %d\n\n",
         openblas_get_config(), par_kind >= 0 && par_kind <= 2 ? par_names[par_kind] : "?",
         blas_threads, omp_get_max_threads());
  printf("| network | batch | callers | OpenBLAS threads | queries/s |\n|---|---|---|---|---|\n");
  struct {
    const char *name;
    int width, blocks, batch;
  } nets[] = {{"decoder 25k", 64, 3, 4096},
              {"decoder 1.06M (paper)", 256, 8, 4096},
              {"decoder 1.06M (paper)", 256, 8, 64}};
  for (size_t c = 0; c < sizeof nets / sizeof *nets; c++) {
    nbrdf_error err;
    nn_spec s;
    die(nn_spec_resmlp(&s, 38, nets[c].width, nets[c].blocks, 1, 1, &err), &err);
    par p = {NULL, {NULL, NULL}, NULL, NULL, nets[c].batch, 1};
    die(nn_create(&s, &p.nn, &err), &err);
    nn_init_params(p.nn, 1);
    for (int t = 0; t < 2; t++)
      die(nn_workspace_create(p.nn, p.batch, NBRDF_NN_INFER, &p.ws[t], &err), &err);
    p.x = calloc((size_t)p.batch * 38, sizeof(float));
    p.y = calloc((size_t)p.batch, sizeof(float));
    for (int setting = 0; setting < 4; setting++) {
      p.callers = setting & 1 ? 2 : 1;
      int bt = setting & 2 ? 1 : blas_threads;
      openblas_set_num_threads(bt); /* process-global: the bench may, the library does not */
      double t = time_calls(par_forward, &p, min_s);
      printf("| %s | %d | %d | %d | %.4g |\n", nets[c].name, p.batch, p.callers, bt, p.batch / t);
      fflush(stdout);
    }
    openblas_set_num_threads(blas_threads);
    free(p.x);
    free(p.y);
    nn_workspace_destroy(p.ws[0]);
    nn_workspace_destroy(p.ws[1]);
    nn_destroy(p.nn);
  }
  printf("\n| sgemm C[m x n] = A[m x k] B | m | n | k | GFLOP/s |\n|---|---|---|---|---|\n");
  int shapes[][3] = {{4096, 256, 256}, {4096, 128, 256}, {4096, 256, 128}, {256, 256, 256}};
  for (size_t s = 0; s < sizeof shapes / sizeof *shapes; s++) {
    gemm_case g = {shapes[s][0], shapes[s][1], shapes[s][2], CblasNoTrans, NULL, NULL, NULL};
    g.a = calloc((size_t)g.m * g.k, sizeof(float));
    g.b = calloc((size_t)g.k * g.n, sizeof(float));
    g.c = calloc((size_t)g.m * g.n, sizeof(float));
    for (int tb = 0; tb < 2; tb++) {
      g.tb = tb ? CblasTrans : CblasNoTrans;
      double t = time_calls(one_gemm, &g, min_s);
      printf("| B %s (%s) | %d | %d | %d | %.1f |\n", tb ? "transposed" : "as stored",
             tb ? "nbrdf forward, W [out x in]" : "W [in x out]", g.m, g.n, g.k,
             2.0 * g.m * g.n * g.k / t / 1e9);
    }
    free(g.a);
    free(g.b);
    free(g.c);
  }
}

static int bench_main(int argc, char **argv);

int main(int argc, char **argv) {
  const char *second = bench_kernels_header(bench_kernels_take_option(&argc, argv));
  int status = bench_main(argc, argv);
  return status == 0 && second ? bench_kernels_rerun(second, argv) : status;
}

static int bench_main(int argc, char **argv) {
  int quick = 0, threads = 0;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--quick"))
      quick = 1;
    else if (!strcmp(argv[i], "--threads"))
      threads = 1;
    else {
      fprintf(stderr, "usage: bench_nn [--quick | --threads] [--kernels OPENBLAS_CORE]\n");
      return 2;
    }
  }
  const double min_s = 0.3;
  if (threads) {
    threads_study(min_s);
    return 0;
  }
  static const int all[] = {1, 16, 256, 4096, 65536}, few[] = {16, 4096};
  const int *batches = quick ? few : all;
  int nb = quick ? 2 : 5;
  printf("OpenBLAS %s, %d threads\n\n", openblas_get_config(), openblas_get_num_threads());
  printf("| network | MACs/query | batch | fwd queries/s | fwd GFLOP/s | sgemm-only GFLOP/s | "
         "fwd fraction | fwd workspace | fwd+bwd samples/s | fwd+bwd GFLOP/s | sgemm-only "
         "GFLOP/s | fwd+bwd fraction | train workspace |\n");
  printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  struct {
    const char *name;
    int in, width, blocks, plain, out;
  } nets[] = {
      {"decoder paper 256x(8+8)", 38, 256, 8, 1, 1}, {"decoder 128x(3+3)", 38, 128, 3, 1, 1},
      {"decoder 64x(3+3)", 38, 64, 3, 1, 1},         {"decoder 32x(2+2)", 38, 32, 2, 1, 1},
      {"layering 512x4", 66, 512, 4, 0, 32},
  };
  for (size_t c = 0; c < sizeof nets / sizeof *nets; c++) {
    nbrdf_error err;
    nn_spec s;
    die(nn_spec_resmlp(&s, nets[c].in, nets[c].width, nets[c].blocks, nets[c].plain, nets[c].out,
                       &err),
        &err);
    bench_network(nets[c].name, &s, batches, nb, min_s);
  }
  return 0;
}
