/* Cost of nbrdf_bake (docs/BAKE.md, "Benchmark"): texels per second and
 * peak RSS of bakes of (a) all-distinct texels and (b) painted-style maps
 * with few distinct tuples, mono and RGB, at the sizes asked for; the rate
 * of the layering network against cblas_sgemm at the network's own shapes;
 * the write time of a baked texture per compression and storage; and the
 * peak RSS of a big RGB bake (memory should grow with the width only).
 *
 * Every bake runs in its own child process (fork), so each peak RSS
 * (wait4's ru_maxrss) is that bake's alone; the input maps are written by
 * another child into a temporary folder first. The parent stays small until
 * the last section, which loads the model itself.
 *
 *   bench_bake [--bundle DIR] [--sizes 1024,4096] [--big 8192] [--dir TMP]
 *              [--cache N] [--device cpu|auto|gpu] [--no-compression] [--no-layering]
 *
 * --big 0 skips the memory check; --cache sets nbrdf_bake_options.tuple_cache.
 * CPU seconds are process CPU time (all threads); wall seconds are printed
 * beside them because the build machine is shared. */
#include <cblas.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench_clock.h"
#include "bench_kernels.h"
#include "model/bundle.h"
#include "nbrdf/bake.h"
#include "nn/nn.h"
#include "texture/latent_exr.h"
#include "texture/oiio_shim.h"

typedef struct bench_cfg {
  const char *bundle, *dir;
  long cache; /* -1: the library's default */
  nbrdf_device device; /* --device: where the networks run (docs/GPU.md) */
} bench_cfg;

/* What a bake child reports through its pipe. */
typedef struct case_result {
  int ok;
  double wall, cpu;
  size_t brdfs, evaluated;
  long long file_bytes;
  char message[512];
} case_result;

static uint64_t mix(uint64_t x) { /* splitmix64 finaliser */
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

static float uniform(uint64_t a, uint64_t b, uint64_t c, float lo, float hi) {
  double u = (double)(mix(a * 0x100000001b3ull ^ mix(b * 31 + c)) >> 11) * 0x1.0p-53;
  return (float)(lo + (hi - lo) * u);
}

static const char *join(const char *dir, const char *name) {
  static char buf[6][1024];
  static int k;
  k = (k + 1) % 6;
  snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
  return buf[k];
}

/* ------------------------------------------------------------ input maps -- */

/* All-distinct content: per-texel noise in alpha1 (mono float), r0 and albedo
 * (one or three channels), a gradient in alpha2, sigma_t in four steps. */
static float distinct_value(int id, int x, int y, int c, int n) {
  switch (id) {
  case NBRDF_BAKE_ALPHA1:
    return uniform(x, y, 11, 0.05f, 0.9f);
  case NBRDF_BAKE_ALPHA2:
    return 0.1f + 0.5f * (float)y / (float)n;
  case NBRDF_BAKE_R0:
    return uniform(x, y, 20 + c, 0.05f, 0.95f);
  case NBRDF_BAKE_ALBEDO:
    return uniform(x, y, 30 + c, 0.2f, 0.95f);
  case NBRDF_BAKE_SIGMA_T: {
    static const float steps[4] = {0.0f, 1.0f, 2.0f, 5.0f};
    return steps[(4 * x) / n];
  }
  default:
    return 1.5f;
  }
}

/* Painted content: flat regions (cells of n/8 texels) taking one of six
 * palette entries, as 8-bit maps: a handful of distinct tuples. */
static float painted_value(int id, int x, int y, int c, int n) {
  static const float palette[6][6] = {
      /* alpha1, eta [0,1] -> [1,2], alpha2, r0, albedo, sigma_t [0,1] -> [0,5] */
      {0.1f, 0.5f, 0.2f, 0.9f, 0.8f, 0.2f},   {0.3f, 0.3f, 0.5f, 0.7f, 0.6f, 0.4f},
      {0.05f, 0.7f, 0.1f, 0.95f, 0.9f, 0.0f}, {0.6f, 0.5f, 0.3f, 0.5f, 0.3f, 1.0f},
      {0.2f, 0.4f, 0.8f, 0.8f, 0.95f, 0.6f},  {0.45f, 0.6f, 0.4f, 0.6f, 0.5f, 0.8f}};
  int cell = n / 8 > 0 ? n / 8 : 1;
  int p = (int)(mix((uint64_t)(x / cell) * 977 + (uint64_t)(y / cell)) % 6);
  float v = palette[p][id];
  return c == 0 ? v : v * (c == 1 ? 0.8f : 0.6f); /* colour maps: tinted channels */
}

/* Writes the six maps (or constants) of a case into `dir`; fills `in`. */
static int write_maps(const char *dir, int n, int painted, int rgb, nbrdf_error *err) {
  static const char *names[NBRDF_BAKE_PARAM_COUNT] = {"alpha1", "eta",    "alpha2",
                                                      "r0",     "albedo", "sigma_t"};
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    if (!painted && id == NBRDF_BAKE_ETA) continue; /* a constant */
    int ch = rgb && (id == NBRDF_BAKE_R0 || id == NBRDF_BAKE_ALBEDO) ? 3 : 1;
    float *px = malloc(sizeof(float) * (size_t)n * n * ch);
    if (!px) return 0;
    for (int y = 0; y < n; y++)
      for (int x = 0; x < n; x++)
        for (int c = 0; c < ch; c++)
          px[((size_t)y * n + x) * ch + c] =
              painted ? painted_value(id, x, y, c, n) : distinct_value(id, x, y, c, n);
    char file[64];
    snprintf(file, sizeof file, "%s.%s", names[id], painted ? "png" : "exr");
    nbrdf_status st = texture_image_write(join(dir, file), n, n, ch, px,
                                          painted ? NBRDF_PIXEL_U8 : NBRDF_PIXEL_FLOAT, err);
    free(px);
    if (st != NBRDF_OK) return 0;
  }
  return 1;
}

static void case_inputs(const char *dir, int painted, nbrdf_bake_inputs *in, char paths[6][1024]) {
  static const char *names[NBRDF_BAKE_PARAM_COUNT] = {"alpha1", "eta",    "alpha2",
                                                      "r0",     "albedo", "sigma_t"};
  nbrdf_bake_inputs d = NBRDF_BAKE_INPUTS_DEFAULT;
  *in = d;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    if (!painted && id == NBRDF_BAKE_ETA) {
      nbrdf_bake_param_constant(&in->param[id], 1.5f);
      continue;
    }
    snprintf(paths[id], 1024, "%s/%s.%s", dir, names[id], painted ? "png" : "exr");
    in->param[id].path = paths[id];
  }
  /* As the CLI's defaults for 8-bit maps. */
  in->param[NBRDF_BAKE_ETA].remap = 1;
  in->param[NBRDF_BAKE_ETA].lo = 1.0f, in->param[NBRDF_BAKE_ETA].hi = 2.0f;
  in->param[NBRDF_BAKE_SIGMA_T].remap = 1;
  in->param[NBRDF_BAKE_SIGMA_T].lo = 0.0f, in->param[NBRDF_BAKE_SIGMA_T].hi = 5.0f;
}

/* ------------------------------------------------------------ children -- */

/* Runs `fn` in a child; returns its peak RSS in KiB (-1 on failure) and
 * copies its result. */
typedef void (*child_fn)(const void *arg, case_result *out);

static long run_child(child_fn fn, const void *arg, case_result *res) {
  int fd[2];
  if (pipe(fd) != 0) return -1;
  fflush(stdout);
  pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    close(fd[0]);
    case_result r;
    memset(&r, 0, sizeof r);
    fn(arg, &r);
    ssize_t w = write(fd[1], &r, sizeof r);
    _exit(w == (ssize_t)sizeof r && r.ok ? 0 : 1);
  }
  close(fd[1]);
  memset(res, 0, sizeof *res);
  ssize_t got = read(fd[0], res, sizeof *res);
  close(fd[0]);
  int status;
  struct rusage ru;
  if (wait4(pid, &status, 0, &ru) != pid || got != (ssize_t)sizeof *res) {
    res->ok = 0;
    return -1;
  }
  return ru.ru_maxrss;
}

typedef struct gen_arg {
  const char *dir;
  int n, painted, rgb;
} gen_arg;

static void gen_child(const void *arg, case_result *out) {
  const gen_arg *g = arg;
  nbrdf_error err = {0};
  double w0 = bench_wall_seconds();
  out->ok = write_maps(g->dir, g->n, g->painted, g->rgb, &err);
  out->wall = bench_wall_seconds() - w0;
  snprintf(out->message, sizeof out->message, "%s", out->ok ? "" : err.message);
}

typedef struct bake_arg {
  const bench_cfg *cfg;
  const char *dir, *out;
  int painted;
  nbrdf_bake_storage storage;
} bake_arg;

static void print_note(void *user, const char *message) {
  (void)user;
  fprintf(stderr, "bench_bake: note: %s\n", message);
}

static void bake_child(const void *arg, case_result *out) {
  const bake_arg *b = arg;
  nbrdf_error err = {0};
  nbrdf_model *model = NULL;
  if (nbrdf_model_load(b->cfg->bundle, &model, &err) != NBRDF_OK) {
    snprintf(out->message, sizeof out->message, "%s", err.message);
    return;
  }
  nbrdf_bake_inputs in;
  char paths[6][1024];
  case_inputs(b->dir, b->painted, &in, paths);
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  o.storage = b->storage;
  if (b->cfg->cache >= 0) o.tuple_cache = (size_t)b->cfg->cache;
  o.device = b->cfg->device;
  o.note = print_note;
  nbrdf_bake_report rep;
  double w0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
  nbrdf_status st = nbrdf_bake(model, &in, &o, b->out, &rep, &err);
  out->wall = bench_wall_seconds() - w0, out->cpu = bench_cpu_seconds() - c0;
  nbrdf_model_destroy(model);
  if (st != NBRDF_OK) {
    snprintf(out->message, sizeof out->message, "%s", err.message);
    return;
  }
  struct stat sb;
  out->file_bytes = stat(b->out, &sb) == 0 ? (long long)sb.st_size : -1;
  out->brdfs = rep.brdfs, out->evaluated = rep.evaluated;
  out->ok = 1;
}

/* One bake case: maps, then the bake; prints a table row. Keeps the output
 * when `keep` names a path to move it to. */
static void bake_case(const bench_cfg *cfg, int n, int painted, int rgb, const char *keep) {
  gen_arg g = {cfg->dir, n, painted, rgb};
  case_result r;
  if (run_child(gen_child, &g, &r) < 0 || !r.ok) {
    printf("| %d² %s %s | maps failed: %s |\n", n, painted ? "painted" : "distinct",
           rgb ? "rgb" : "mono", r.message);
    return;
  }
  double gen_s = r.wall;
  bake_arg b = {cfg, cfg->dir, join(cfg->dir, "out.exr"), painted, NBRDF_BAKE_HALF};
  long rss = run_child(bake_child, &b, &r);
  char load[128];
  bench_load_line(load, sizeof load);
  if (rss < 0 || !r.ok) {
    printf("| %d² %s %s | bake failed: %s |\n", n, painted ? "painted" : "distinct",
           rgb ? "rgb" : "mono", r.message);
    return;
  }
  double texels = (double)n * n;
  printf("| %d² | %s | %s | %zu | %zu | %.1f | %.1f | %.3g | %.3g | %.0f | %.1f | %.1f | %s |\n", n,
         painted ? "painted" : "distinct", rgb ? "rgb" : "mono", r.brdfs, r.evaluated, r.wall,
         r.cpu, texels / r.wall, texels / r.cpu, rss / 1024.0, r.file_bytes / 1048576.0, gen_s,
         load);
  if (keep) {
    if (rename(b.out, keep) != 0) perror(keep);
  } else {
    unlink(b.out);
  }
}

static void remove_maps(const char *dir) {
  static const char *names[] = {"alpha1", "eta", "alpha2", "r0", "albedo", "sigma_t"};
  char file[64];
  for (int i = 0; i < 6; i++)
    for (int e = 0; e < 2; e++) {
      snprintf(file, sizeof file, "%s.%s", names[i], e ? "png" : "exr");
      unlink(join(dir, file));
    }
}

/* ------------------------------------------------------- compression -- */

typedef struct write_arg {
  const char *src, *dir;
  texture_latent_compression compression;
  texture_latent_storage storage;
} write_arg;

/* Reads level 0 of a baked texture and writes it again (level 0 only, so
 * the figure is the writer's, not the mip proxy's) with one compression. */
static void write_child(const void *arg, case_result *out) {
  const write_arg *a = arg;
  nbrdf_error err = {0};
  texture_latent_reader *r = NULL;
  if (texture_latent_reader_open(&r, a->src, &err) != NBRDF_OK) {
    snprintf(out->message, sizeof out->message, "%s", err.message);
    return;
  }
  texture_latent_info info = *texture_latent_reader_info(r);
  int W = info.width, H = info.height, C = info.channels;
  float *texels = malloc(sizeof(float) * (size_t)W * H * C);
  if (!texels || texture_latent_reader_read(r, 0, 0, 0, W, H, texels, &err) != NBRDF_OK) {
    snprintf(out->message, sizeof out->message, "%s", texels ? err.message : "out of memory");
    texture_latent_reader_close(r);
    free(texels);
    return;
  }
  texture_latent_layout layout = info.layout;
  texture_latent_reader_close(r);
  texture_latent_exr_options o = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  o.storage = a->storage, o.compression = a->compression, o.mip_levels = 1;
  const char *path = join(a->dir, "rewrite.exr");
  texture_latent_writer *w = NULL;
  double w0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
  nbrdf_status st = texture_latent_writer_create(&w, path, W, H, &layout, NULL, &o, NULL, 0, &err);
  for (int y = 0; st == NBRDF_OK && y < H; y += 64) {
    int rows = H - y < 64 ? H - y : 64;
    st = texture_latent_writer_write_rows(w, texels + (size_t)y * W * C, rows, &err);
  }
  if (st == NBRDF_OK) {
    st = texture_latent_writer_finish(w, &err);
    w = NULL;
  }
  texture_latent_writer_abort(w);
  out->wall = bench_wall_seconds() - w0, out->cpu = bench_cpu_seconds() - c0;
  if (st == NBRDF_OK) {
    struct stat sb;
    out->file_bytes = stat(path, &sb) == 0 ? (long long)sb.st_size : -1;
    /* Read time of the whole level, for the half-vs-float choice. */
    double r0 = bench_wall_seconds();
    if (texture_latent_reader_open(&r, path, &err) == NBRDF_OK) {
      st = texture_latent_reader_read(r, 0, 0, 0, W, H, texels, &err);
      texture_latent_reader_close(r);
    }
    out->brdfs = (size_t)(1e6 * (bench_wall_seconds() - r0)); /* read microseconds */
    out->ok = st == NBRDF_OK;
  }
  if (st != NBRDF_OK) snprintf(out->message, sizeof out->message, "%s", err.message);
  unlink(path);
  free(texels);
}

static void compression_table(const bench_cfg *cfg, const char *src) {
  printf("\nEXR write of a baked 1024² RGB all-distinct texture (level 0 only, 102 channels), "
         "per compression and storage:\n\n");
  printf("| storage | compression | MiB | write wall s | write CPU s | read wall s | load |\n");
  printf("|---|---|---:|---:|---:|---:|---|\n");
  static const texture_latent_compression comps[] = {NBRDF_LATENT_ZIP, NBRDF_LATENT_PIZ,
                                                     NBRDF_LATENT_RLE, NBRDF_LATENT_NONE};
  for (int s = 0; s < 2; s++)
    for (size_t c = 0; c < sizeof comps / sizeof *comps; c++) {
      write_arg a = {src, cfg->dir, comps[c], s ? NBRDF_LATENT_FLOAT : NBRDF_LATENT_HALF};
      case_result r;
      char load[128];
      long rss = run_child(write_child, &a, &r);
      bench_load_line(load, sizeof load);
      if (rss < 0 || !r.ok) {
        printf("| %s | %s | failed: %s |\n", texture_latent_storage_name(a.storage),
               texture_latent_compression_name(a.compression), r.message);
        continue;
      }
      printf("| %s | %s | %.1f | %.2f | %.2f | %.2f | %s |\n",
             texture_latent_storage_name(a.storage), texture_latent_compression_name(a.compression),
             r.file_bytes / 1048576.0, r.wall, r.cpu, r.brdfs * 1e-6, load);
    }
}

/* ------------------------------------------------------------ layering -- */

/* Seconds (CPU) per call of the GEMMs the network `spec` makes for `batch`
 * rows, timed with cblas_sgemm on the same shapes (y = x W^T). */
static double sgemm_seconds(const nn_spec *spec, int batch, double *flops) {
  int shapes[3 * NBRDF_NN_MAX_LAYERS][2], n = 0;
  for (int i = 0; i < spec->n_layers; i++) {
    const nn_layer_spec *l = &spec->layers[i];
    int in = nn_spec_width(spec, i), out = nn_spec_width(spec, i + 1);
    if (l->kind == NBRDF_NN_LINEAR || l->kind == NBRDF_NN_PLAIN) {
      shapes[n][0] = in, shapes[n++][1] = out;
    } else if (l->kind == NBRDF_NN_RESIDUAL) {
      int h = l->hidden > 0 ? l->hidden : in / 2;
      shapes[n][0] = in, shapes[n++][1] = h;
      shapes[n][0] = h, shapes[n++][1] = in;
    }
    if (l->has_skip && nn_spec_width(spec, l->skip_from) != out)
      shapes[n][0] = nn_spec_width(spec, l->skip_from), shapes[n++][1] = out;
  }
  int maxw = 1;
  *flops = 0;
  for (int s = 0; s < n; s++) {
    maxw = shapes[s][0] > maxw ? shapes[s][0] : maxw;
    maxw = shapes[s][1] > maxw ? shapes[s][1] : maxw;
    *flops += 2.0 * batch * shapes[s][0] * shapes[s][1];
  }
  float *x = malloc(sizeof(float) * batch * maxw), *y = malloc(sizeof(float) * batch * maxw);
  float *w = malloc(sizeof(float) * maxw * maxw);
  for (size_t i = 0; i < (size_t)batch * maxw; i++)
    x[i] = (float)(i % 7) * 0.1f;
  for (size_t i = 0; i < (size_t)maxw * maxw; i++)
    w[i] = (float)(i % 5) * 0.01f;
  int reps = 0;
  double c0 = bench_cpu_seconds();
  do {
    for (int s = 0; s < n; s++)
      cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasTrans, batch, shapes[s][1], shapes[s][0], 1.0f,
                  x, shapes[s][0], w, shapes[s][0], 0.0f, y, shapes[s][1]);
    reps++;
  } while (bench_cpu_seconds() - c0 < 2.0);
  double t = (bench_cpu_seconds() - c0) / reps;
  free(x), free(y), free(w);
  return t;
}

static int layering_table(const bench_cfg *cfg) {
  nbrdf_error err = {0};
  nbrdf_model *model = NULL;
  if (nbrdf_model_load(cfg->bundle, &model, &err) != NBRDF_OK) {
    fprintf(stderr, "bench_bake: %s\n", err.message);
    return 1;
  }
  const int D = nbrdf_model_latent_dim(model);
  const size_t n = 16384; /* the bake's evaluation chunk */
  float *top = malloc(sizeof(float) * n * D * 3), *bottom = top + n * D, *out = bottom + n * D;
  float *albedo = malloc(sizeof(float) * n * 2), *sigma_t = albedo + n;
  float *a = malloc(sizeof(float) * n * 2), *b = a + n;
  for (size_t k = 0; k < n; k++) {
    a[k] = uniform(k, 1, 1, 0.05f, 0.9f), b[k] = uniform(k, 2, 2, 1.1f, 1.9f);
    albedo[k] = uniform(k, 3, 3, 0.2f, 0.95f), sigma_t[k] = uniform(k, 4, 4, 0.0f, 5.0f);
  }
  nbrdf_status st = nbrdf_model_base_latents(model, NBRDF_BASE_DIELECTRIC, n, a, b,
                                             NBRDF_RANGE_CLAMP, top, NULL, &err);
  for (size_t k = 0; k < n; k++)
    b[k] = uniform(k, 5, 5, 0.05f, 0.95f);
  if (st == NBRDF_OK)
    st = nbrdf_model_base_latents(model, NBRDF_BASE_CONDUCTOR, n, a, b, NBRDF_RANGE_CLAMP, bottom,
                                  NULL, &err);
  int reps = 0;
  double w0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
  while (st == NBRDF_OK && (reps < 2 || bench_cpu_seconds() - c0 < 3.0)) {
    st = nbrdf_model_layer(model, n, top, bottom, albedo, sigma_t, out, &err);
    reps++;
  }
  double lw = (bench_wall_seconds() - w0) / reps, lc = (bench_cpu_seconds() - c0) / reps;
  if (st != NBRDF_OK) {
    fprintf(stderr, "bench_bake: %s\n", err.message);
    return 1;
  }
  const nn_spec *spec = nn_get_spec(model->layering->nn);
  double flops, sg = sgemm_seconds(spec, 4096, &flops); /* nbrdf_model_layer's batch */
  double lflops = 2.0 * (double)nbrdf_model_layering_macs(model) * n;
  double big_flops, big = 0;
  {
    nn_spec sq;
    nn_spec_init(&sq, 1024);
    nn_spec_add(&sq, NBRDF_NN_LINEAR, 1024);
    big = sgemm_seconds(&sq, 4096, &big_flops);
  }
  char load[128];
  bench_load_line(load, sizeof load);
  printf("\nLayering network (bundle %s, %lld MACs per evaluation), %zu evaluations per call:\n\n",
         nbrdf_model_name(model), (long long)nbrdf_model_layering_macs(model), n);
  printf("| quantity | value |\n|---|---|\n");
  printf("| nbrdf_model_layer: evaluations per CPU-second | %.3g (%.3g per wall-second) |\n",
         n / lc, n / lw);
  printf("| nbrdf_model_layer: GFLOP/s (2 x MACs, CPU time) | %.2f |\n", lflops / lc * 1e-9);
  printf("| cblas_sgemm at the network's shapes (batch 4096), GFLOP/s (CPU time) | %.2f |\n",
         flops / sg * 1e-9);
  printf("| layering as a fraction of that sgemm rate | %.0f %% |\n",
         100.0 * (lflops / lc) / (flops / sg));
  printf("| cblas_sgemm 4096x1024x1024, GFLOP/s (CPU time), for scale | %.2f |\n",
         big_flops / big * 1e-9);
  printf("| load average | %s |\n", load);
  free(top), free(albedo), free(a);
  nbrdf_model_destroy(model);
  return 0;
}

/* ---------------------------------------------------------------- main -- */

static int bench_main(int argc, char **argv);

int main(int argc, char **argv) {
  const char *second = bench_kernels_header(bench_kernels_take_option(&argc, argv));
  int status = bench_main(argc, argv);
  return status == 0 && second ? bench_kernels_rerun(second, argv) : status;
}

static int bench_main(int argc, char **argv) {
  bench_cfg cfg = {"models/default", NULL, -1, NBRDF_DEVICE_CPU};
  char sizes[128] = "1024";
  int big = 8192, compression = 1, layering = 1;
  for (int i = 1; i < argc; i++) {
    const char *v = i + 1 < argc ? argv[i + 1] : NULL;
    if (!strcmp(argv[i], "--bundle") && v)
      cfg.bundle = v, i++;
    else if (!strcmp(argv[i], "--sizes") && v)
      snprintf(sizes, sizeof sizes, "%s", v), i++;
    else if (!strcmp(argv[i], "--big") && v)
      big = atoi(v), i++;
    else if (!strcmp(argv[i], "--dir") && v)
      cfg.dir = v, i++;
    else if (!strcmp(argv[i], "--cache") && v)
      cfg.cache = atol(v), i++;
    else if (!strcmp(argv[i], "--device") && v && nbrdf_device_parse(v) >= 0)
      cfg.device = (nbrdf_device)nbrdf_device_parse(v), i++;
    else if (!strcmp(argv[i], "--no-compression"))
      compression = 0;
    else if (!strcmp(argv[i], "--no-layering"))
      layering = 0;
    else {
      fprintf(stderr, "usage: bench_bake [--bundle DIR] [--sizes 1024,4096] [--big 8192] "
                      "[--dir TMP] [--cache N] [--device cpu|auto|gpu] [--no-compression] [--no-layering] "
                      "[--kernels OPENBLAS_CORE]\n");
      return 2;
    }
  }
  char tmpl[] = "/tmp/bench_bake_XXXXXX";
  if (!cfg.dir && !(cfg.dir = mkdtemp(tmpl))) {
    perror("bench_bake: mkdtemp");
    return 1;
  }
  const char *blas = getenv("OPENBLAS_NUM_THREADS"), *omp = getenv("OMP_NUM_THREADS");
  printf("bench_bake: bundle %s, maps in %s, OPENBLAS_NUM_THREADS=%s OMP_NUM_THREADS=%s, "
         "tuple cache %s, device %s\n\n",
         cfg.bundle, cfg.dir, blas ? blas : "(unset)", omp ? omp : "(unset)",
         cfg.cache < 0 ? "default" : (cfg.cache ? "on" : "off"), nbrdf_device_name(cfg.device));
  printf("| size | content | colour | BRDFs | evaluated | wall s | CPU s | texels/wall-s | "
         "texels/CPU-s | peak RSS MiB | file MiB | maps s | load (1, 5, 15 min) |\n");
  printf("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
  char kept[1100] = "";
  for (char *s = strtok(sizes, ","); s; s = strtok(NULL, ",")) {
    int n = atoi(s);
    if (n < 1) continue;
    for (int painted = 1; painted >= 0; painted--)
      for (int rgb = 0; rgb < 2; rgb++) {
        const char *keep = NULL;
        if (compression && !painted && rgb && n == 1024) {
          snprintf(kept, sizeof kept, "%s", join(cfg.dir, "distinct-rgb-1024.exr"));
          keep = kept;
        }
        bake_case(&cfg, n, painted, rgb, keep);
        remove_maps(cfg.dir);
      }
  }
  if (big > 0) {
    printf("\nMemory check (painted RGB maps, the full mip chain):\n\n");
    printf("| size | content | colour | BRDFs | evaluated | wall s | CPU s | texels/wall-s | "
           "texels/CPU-s | peak RSS MiB | file MiB | maps s | load (1, 5, 15 min) |\n");
    printf("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
    bake_case(&cfg, big, 1, 1, NULL);
    remove_maps(cfg.dir);
  }
  if (compression && kept[0]) {
    compression_table(&cfg, kept);
    unlink(kept);
  }
  int rc = layering ? layering_table(&cfg) : 0;
  if (!strncmp(cfg.dir, "/tmp/bench_bake_", 16)) rmdir(cfg.dir);
  return rc;
}
