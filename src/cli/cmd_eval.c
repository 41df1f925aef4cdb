/* nbrdf eval: point queries of the ground-truth BRDFs, CSV in, CSV out.
 * Its output is what an independent implementation of the same
 * physics is checked against, so the format is strict and fully documented in
 * cmd_eval_usage(). */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "cli/cli_device.h"
#include "cli/eval_neural.h"
#include "cli/eval_texture.h"
#include "core/csv.h"
#include "core/csv_columns.h"
#include "core/input_file.h"
#include "core/vec3.h"
#include "model/material.h"
#include "nbrdf/brdf.h"

enum { MAX_PARAMS = 6, N_ANGLES = 4, MAX_COLUMNS = MAX_PARAMS + N_ANGLES };

typedef core_csv_column column_spec;

typedef struct model_spec {
  const char *name;
  int stochastic;
  cli_eval_neural_kind neural; /* CLI_EVAL_NEURAL_NONE: the ground truth */
  int n_params;
  column_spec params[MAX_PARAMS];
} model_spec;

#define ALPHA_RANGE NBRDF_GT_ALPHA_MIN, NBRDF_GT_ALPHA_MAX, 0
#define ETA_RANGE NBRDF_GT_ETA_MIN, NBRDF_GT_ETA_MAX, 0
/* The neural models accept any finite number here: the bake's own checks
 * (src/bake/bake_tuple.h) then refuse, clamp or keep it exactly as a bake
 * would. */
#define ANY -INFINITY, INFINITY, 0
// clang-format off
#define LAYERED_COLUMNS                                                                            \
  {{"alpha1", ALPHA_RANGE}, {"eta", ETA_RANGE}, {"alpha2", ALPHA_RANGE},                          \
   {"r0", 0, 1, 0}, {"albedo", 0, 1, 0}, {"sigma_t", 0, NBRDF_GT_SIGMA_T_MAX, 0}}
#define NEURAL_COLUMNS                                                                             \
  {{"alpha1", ANY}, {"eta", ANY}, {"alpha2", ANY}, {"r0", ANY}, {"albedo", ANY}, {"sigma_t", ANY}}
// clang-format on
static const model_spec MODELS[] = {
    {"layered", 1, CLI_EVAL_NEURAL_NONE, 6, LAYERED_COLUMNS},
    {"conductor", 0, CLI_EVAL_NEURAL_NONE, 2, {{"alpha", ALPHA_RANGE}, {"r0", 0, 1, 0}}},
    {"dielectric", 0, CLI_EVAL_NEURAL_NONE, 2, {{"alpha", ALPHA_RANGE}, {"eta", ETA_RANGE}}},
    {"neural", 0, CLI_EVAL_NEURAL_LAYERED, 6, NEURAL_COLUMNS},
    {"neural-conductor", 0, CLI_EVAL_NEURAL_CONDUCTOR, 2, {{"alpha", ANY}, {"r0", ANY}}},
    {"neural-dielectric", 0, CLI_EVAL_NEURAL_DIELECTRIC, 2, {{"alpha", ANY}, {"eta", ANY}}},
};
static const column_spec ANGLES[N_ANGLES] = {
    {"theta_i", 0, 90, 1}, {"phi_i", -360, 360, 0}, {"theta_o", 0, 90, 1}, {"phi_o", -360, 360, 0}};

typedef struct eval_args {
  const model_spec *model;
  nbrdf_eval_options options;
  cli_eval_neural_options neural;
  int neural_option;                /* an option of the neural models was given */
  cli_eval_texture_options texture; /* texture.texture != NULL: --texture mode */
  int level_given, model_option, device_given;
  const char *in; /* --in FILE, else stdin */
  int model_k;    /* index into MODELS, -1: none */
  int seen_bundle, seen_roughness, seen_range, seen_spp, seen_threads, seen_seed;
} eval_args;

static int read_level(const char *cmd, const cli_opt *o, const char *v) {
  cli_eval_texture_options *t = o->dest;
  uint64_t level;
  if (!cli_parse_index(v, &level))
    return cli_opt_bad(cmd, o->name, "a mip level (an integer, 0 the full size)", v);
  /* Which levels exist is the texture's to say, whatever the number's size. */
  t->level = level > INT_MAX ? INT_MAX : (int)level;
  t->level_text = v;
  return 0;
}

static void eval_options(eval_args *a, cli_opt_visit visit, void *user) {
  // clang-format off
  const cli_opt t[] = {
      {.type = CLI_OPT_ENUM, .name = "--model", .meta = "M",
       .choices = "layered|conductor|dielectric|neural|neural-conductor|neural-dielectric",
       .dest = &a->model_k,
       .help = "layered, conductor, dielectric (ground truth) or neural,\n"
               "neural-conductor, neural-dielectric (a bundle) (required)"},
      {.type = CLI_OPT_INT, .name = "--spp", .meta = "N", .lo = 1, .hi = 1e9,
       .dest = &a->options.spp, .seen = &a->seen_spp,
       .help = "random walks per query for stochastic models (default\n"
               "1024); ignored by the analytic models"},
      {.type = CLI_OPT_U64, .name = "--seed", .meta = "S", .dest = &a->options.seed,
       .seen = &a->seen_seed, .help = "base seed, an unsigned 64-bit integer (default 0)"},
      {.type = CLI_OPT_INT, .name = "--threads", .meta = "T", .lo = 0, .hi = 4096,
       .dest = &a->options.threads, .seen = &a->seen_threads,
       .help = "worker threads; 0 = all cores (default 0)"},
      {.type = CLI_OPT_PATH, .name = "--bundle", .meta = "DIR", .dest = &a->neural.bundle,
       .seen = &a->seen_bundle,
       .help = "neural models and --texture: the bundle (default: the\n"
               "default bundle, see 'nbrdf --version')"},
      {.type = CLI_OPT_ENUM, .name = "--roughness", .choices = "alpha|perceptual",
       .dest = &a->neural.roughness, .seen = &a->seen_roughness,
       .help = "neural models only: as for 'nbrdf bake' (default alpha)"},
      {.type = CLI_OPT_ENUM, .name = "--range", .choices = "clamp|refuse", .dest = &a->neural.range,
       .seen = &a->seen_range, .help = "neural models only: as for 'nbrdf bake' (default clamp)"},
      {.type = CLI_OPT_PATH, .name = "--texture", .meta = "FILE", .dest = &a->texture.texture,
       .help = "a latent texture baked with the bundle (--bundle DIR, as for\n"
               "the neural models): decoded as a renderer decodes it, with the\n"
               "texture's own decoder when it carries one (format version 2,\n"
               "docs/LATENT-TEXTURE.md), else the bundle's"},
      {.type = CLI_OPT_CUSTOM, .name = "--level", .meta = "K", .dest = &a->texture,
       .seen = &a->level_given, .parse = read_level,
       .help = "--texture: the mip level to fetch from (default 0)"},
      {.type = CLI_OPT_ENUM, .name = "--device", .dest = &a->texture.device,
       .choices = "auto|cpu|gpu", .values = cli_device_values, .seen = &a->device_given,
       .help = "--texture: the decoder's device (default $NBRDF_DEVICE,\n"
               "else auto: a GPU where Vulkan has one, else the CPU with a note;\n"
               "docs/GPU.md)"},
      {.type = CLI_OPT_PATH, .name = "--in", .meta = "FILE", .dest = &a->in,
       .help = "read the CSV from FILE instead of stdin"},
      {0},
  };
  // clang-format on
  visit(user, NULL, t);
}

static void eval_args_init(eval_args *a) {
  memset(a, 0, sizeof *a);
  a->model_k = -1;
  a->neural = (cli_eval_neural_options){NULL, NBRDF_ROUGHNESS_ALPHA, NBRDF_RANGE_CLAMP};
  a->options = (nbrdf_eval_options)NBRDF_EVAL_OPTIONS_DEFAULT;
  a->texture = (cli_eval_texture_options){NULL, NULL, 0, NULL, NBRDF_DEVICE_AUTO, "stdin"};
}

void cmd_eval_options(cli_opt_visit visit, void *user) {
  eval_args a;
  eval_args_init(&a);
  eval_options(&a, visit, user);
}

void cmd_eval_usage(FILE *out) {
  fprintf(out, "usage: nbrdf eval --model layered|conductor|dielectric [--spp N] "
               "[--seed S] [--threads T]\n"
               "       nbrdf eval --model neural|neural-conductor|neural-dielectric "
               "[--bundle DIR]\n"
               "                  [--roughness alpha|perceptual] [--range clamp|refuse]\n"
               "       nbrdf eval --texture FILE.exr [--level K] [--bundle DIR]\n"
               "\n"
               "Evaluates ground-truth or neural BRDF values, or a baked latent texture, at point\n"
               "queries: reads CSV on stdin (or --in FILE), writes CSV on stdout. A line holds at\n"
               "most 65536 bytes; values are decimal numbers (white space around them allowed;\n"
               "no hex, inf or nan).\n"
               "\n"
               "options:\n");
  cmd_eval_options(cli_options_help_visit, out);
  fprintf(out,
          "\n"
          "input: a header row naming the columns, then one query per row. Columns "
          "may come in\n"
          "any order; columns the model does not use are passed through "
          "unchanged.\n"
          "  layered:    alpha1,eta,alpha2,r0,albedo,sigma_t + angles\n"
          "              rough dielectric coat (alpha1, eta) over a slab of unit "
          "thickness with\n"
          "              optical depth sigma_t and single-scattering albedo "
          "(isotropic phase),\n"
          "              over a rough conductor (alpha2, r0)\n"
          "  conductor:  alpha,r0 + angles      (GGX, Schlick Fresnel with normal "
          "reflectance r0)\n"
          "  dielectric: alpha,eta + angles     (GGX, exact Fresnel; its "
          "reflection lobe only)\n"
          "  neural, neural-conductor, neural-dielectric: the columns of layered, "
          "conductor,\n"
          "              dielectric; f exactly as a bake with the same options computes "
          "a texel,\n"
          "              through the bake's own code: roughness convention, range "
          "checks, base-table\n"
          "              look-up, layering network, then the decoder (a --float bake's "
          "texel; a half\n"
          "              bake rounds the latent to 16 bits). A value outside the "
          "model's trained\n"
          "              range (the bundle's table grids for alpha1, eta, alpha2, r0; "
          "sigma_t 0..5)\n"
          "              is clamped onto it with a warning naming the line, as the bake "
          "does, or\n"
          "              refused with --range refuse; negative values and r0 or albedo "
          "above 1 are\n"
          "              refused.\n"
          "  --texture:  u,v + angles; u, v in [0, 1] texture coordinates (u to the right,\n"
          "              v DOWN from the first row of the image, as the renderer and the\n"
          "              shaders fetch), the latents fetched bilinearly in level K between\n"
          "              the four nearest texel centres (the texture repeats: u = 0 and\n"
          "              u = 1 are the same place), every colour channel decoded\n"
          "  angles:     theta_i,phi_i,theta_o,phi_o in DEGREES; theta from the "
          "surface normal,\n"
          "              phi the azimuth from the x axis; both directions point "
          "away from the\n"
          "              surface (wi towards the light, wo towards the viewer)\n"
          "\n"
          "accepted ranges (anything else, NaN or Inf stops with an error naming "
          "the row):\n"
          "  alpha, alpha1, alpha2  [%g, %g]  GGX roughness, used directly (no "
          "remapping)\n"
          "  eta                    [%g, %g]  coat IOR relative to the outside\n"
          "  r0, albedo             [0, 1]\n"
          "  sigma_t                [0, %g]  optical depth of the slab\n"
          "  theta_i, theta_o       [0, 90)   degrees\n"
          "  phi_i, phi_o           [-360, 360] degrees\n"
          "The neural models take what a bake takes instead: any finite value >= 0 "
          "(r0, albedo\n"
          "at most 1), clamped to the trained ranges as described above.\n"
          "\n"
          "output: the input columns in input order, then\n"
          "  f          the BRDF value f(wi, wo) in 1/sr, WITHOUT the cosine "
          "factor\n"
          "  f_stderr   (layered only) the standard error of f, a Monte Carlo mean "
          "over N walks\n"
          "  --texture: f for a mono texture, f_r,f_g,f_b for an RGB one, printed with\n"
          "             %%.9g (the decoder's float exactly)\n"
          "Numbers are printed with %%.17g, which round-trips a double exactly. "
          "Output lines end\n"
          "in LF. Row k always uses random stream k of the seed, so the output "
          "depends on the\n"
          "seed and the row order but not on --threads.\n"
          "\n"
          "format details: LF or CRLF line endings; blank lines are skipped; "
          "fields may be quoted\n"
          "(RFC 4180); spaces around numbers are ignored; a header without rows "
          "gives a header\n"
          "without rows. The input must not already have a column 'f' or "
          "'f_stderr'\n"
          "(--texture: one of its output columns).\n"
          "\n"
          "exit status: 0 success; 1 bad input (the message names the line and "
          "column, e.g.\n"
          "\"stdin:7: column 'eta' expects a number in [1, 4], got 'abc'\"); 2 bad usage.\n"
          "\n"
          "example:\n"
          "  printf 'alpha,r0,theta_i,phi_i,theta_o,phi_o\\n0.5,1,0,0,0,0\\n' |\n"
          "    nbrdf eval --model conductor\n"
          "  printf 'u,v,theta_i,phi_i,theta_o,phi_o\\n0.5,0.5,30,0,30,180\\n' |\n"
          "    nbrdf eval --texture out.exr\n",
          NBRDF_GT_ALPHA_MIN, NBRDF_GT_ALPHA_MAX, NBRDF_GT_ETA_MIN, NBRDF_GT_ETA_MAX,
          NBRDF_GT_SIGMA_T_MAX);
}

static int parse_args(int argc, char **argv, eval_args *a) {
  eval_args_init(a);
  if (cli_device_default("eval", &a->texture.device) < 0) return CLI_EXIT_USAGE;
  cli_parse_call call = {"eval", NULL, argc, 1, argv, NULL, 0};
  eval_options(a, cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) {
    cmd_eval_usage(stdout);
    return -1;
  }
  if (call.rc != CLI_OPTIONS_OK) return call.rc;
  a->model = a->model_k >= 0 ? &MODELS[a->model_k] : NULL;
  a->texture.bundle = a->neural.bundle;
  a->neural_option = a->seen_bundle || a->seen_roughness || a->seen_range;
  a->model_option =
      a->seen_roughness || a->seen_range || a->seen_spp || a->seen_threads || a->seen_seed;
  if (a->texture.texture) {
    if (a->model || a->model_option)
      return cli_usage_error("eval",
                             "--texture decodes the texture: --model, --roughness, --range, "
                             "--spp, --threads and --seed do not apply");
    return CLI_EXIT_OK;
  }
  if (a->level_given) return cli_usage_error("eval", "--level applies to --texture only");
  if (a->device_given) return cli_usage_error("eval", "--device applies to --texture only");
  if (!a->model) return cli_usage_error("eval", "--model or --texture is required");
  if (a->neural_option && !a->model->neural)
    return cli_usage_error("eval",
                           "--bundle, --roughness and --range apply to the neural models only");
  return CLI_EXIT_OK;
}

/* Columns of the model's parameters then the four angles, as header indices. */
typedef struct layout {
  const char *input; /* the CSV's name in messages: the --in FILE, or "stdin" */
  int n;
  const column_spec *spec[MAX_COLUMNS];
  size_t index[MAX_COLUMNS];
} layout;

static int find_columns(const core_csv_table *t, const model_spec *m, layout *lay) {
  static const char *const reserved[] = {"f", "f_stderr", NULL};
  lay->n = m->n_params + N_ANGLES;
  for (int c = 0; c < lay->n; c++)
    lay->spec[c] = c < m->n_params ? &m->params[c] : &ANGLES[c - m->n_params];
  char needs[160];
  int k = snprintf(needs, sizeof needs, "model %s needs ", m->name);
  for (int p = 0; p < m->n_params; p++)
    k += snprintf(needs + k, sizeof needs - (size_t)k, "%s%s", p ? "," : "", m->params[p].name);
  snprintf(needs + k, sizeof needs - (size_t)k, " and the angles");
  nbrdf_error err = {0};
  if (core_csv_columns_find(t, lay->input, lay->spec, lay->n, reserved, needs, lay->index, &err))
    return cli_fail_error("eval", &err);
  return CLI_EXIT_OK;
}

/* Parses and range-checks the model's columns of one row into v[]. */
static int parse_row(const core_csv_table *t, size_t r, const layout *lay, double *v) {
  nbrdf_error err = {0};
  if (core_csv_columns_read(t, lay->input, r, lay->spec, lay->index, lay->n, v, &err))
    return cli_fail_error("eval", &err);
  return CLI_EXIT_OK;
}

static nbrdf_status create_brdf(const model_spec *m, const double *p, nbrdf_brdf **out,
                                nbrdf_error *err) {
  if (!strcmp(m->name, "conductor")) return nbrdf_brdf_create_conductor(p[0], p[1], out, err);
  if (!strcmp(m->name, "dielectric")) return nbrdf_brdf_create_dielectric(p[0], p[1], out, err);
  return model_material_truth(p, out, err); /* the layered columns are the material's, in order */
}

static void direction(double theta_deg, double phi_deg, double w[3]) {
  vec3 d = v3_from_spherical(theta_deg * (M_PI / 180.0), phi_deg * (M_PI / 180.0));
  w[0] = d.x, w[1] = d.y, w[2] = d.z;
}

typedef struct batch {
  double *params; /* neural models: n × n_params */
  size_t n, n_owned;
  const nbrdf_brdf **brdfs;
  nbrdf_brdf **owned;
  nbrdf_query *queries;
  double *f, *f_stderr;
} batch;

static void batch_free(batch *b) {
  for (size_t k = 0; k < b->n_owned; k++)
    nbrdf_brdf_destroy(b->owned[k]);
  free(b->brdfs), free(b->owned), free(b->queries), free(b->f), free(b->f_stderr), free(b->params);
}

/* One handle per row, shared by consecutive rows with the same parameters
 * (a lobe scan repeats them), so memory stays linear and small. */
static int build_batch(const core_csv_table *t, const eval_args *a, const layout *lay, batch *b) {
  size_t n = t->n_records - 1;
  b->n = n;
  b->brdfs = calloc(n ? n : 1, sizeof *b->brdfs);
  b->owned = calloc(n ? n : 1, sizeof *b->owned);
  b->queries = calloc(n ? n : 1, sizeof *b->queries);
  b->f = calloc(n ? n : 1, sizeof *b->f);
  b->f_stderr = calloc(n ? n : 1, sizeof *b->f_stderr);
  b->params = calloc((n ? n : 1) * MAX_PARAMS, sizeof *b->params);
  if (!b->brdfs || !b->owned || !b->queries || !b->f || !b->f_stderr || !b->params)
    return cli_fail("eval", "out of memory for %zu rows", n);
  const int np = a->model->n_params;
  double prev[MAX_COLUMNS];
  for (size_t k = 0; k < n; k++) {
    double v[MAX_COLUMNS];
    int rc = parse_row(t, k + 1, lay, v);
    if (rc != CLI_EXIT_OK) return rc;
    memcpy(b->params + k * (size_t)np, v, (size_t)np * sizeof *v);
    if (a->model->neural) {
      /* no ground-truth handle */
    } else if (k > 0 && !memcmp(v, prev, (size_t)np * sizeof *v)) {
      b->brdfs[k] = b->brdfs[k - 1];
    } else {
      nbrdf_error err = {0};
      nbrdf_brdf *h = NULL;
      if (create_brdf(a->model, v, &h, &err) != NBRDF_OK) {
        return cli_fail("eval", "line %zu: %s", t->line[k + 1], err.message);
      }
      b->owned[b->n_owned++] = h;
      b->brdfs[k] = h;
    }
    memcpy(prev, v, sizeof prev);
    direction(v[np + 0], v[np + 1], b->queries[k].wi);
    direction(v[np + 2], v[np + 3], b->queries[k].wo);
  }
  return CLI_EXIT_OK;
}

static void write_row(FILE *out, const core_csv_table *t, size_t r) {
  size_t width = core_csv_record_width(t, r);
  for (size_t c = 0; c < width; c++) {
    if (c) fputc(',', out);
    core_csv_write_raw(out, t, r, c);
  }
}

/* The CSV of --in FILE, else of stdin. Read once from start to end, so FILE may be a FIFO or
 * a pipe (`--in <(cmd)`) as stdin may; the reader bounds each line. */
static int read_input(const char *path, core_csv_table *t) {
  nbrdf_error err = {0};
  FILE *in = stdin;
  if (path) {
    int fd = -1;
    if (core_input_open_stream(path, &fd, &err) != NBRDF_OK) return cli_fail_error("eval", &err);
    in = fdopen(fd, "rb");
    if (!in) {
      close(fd);
      return cli_fail("eval", "%s: cannot read", path);
    }
  } else if (isatty(STDIN_FILENO)) {
    fprintf(stderr, "nbrdf eval: reading CSV from the terminal (end with Ctrl-D; see --help)\n");
  }
  nbrdf_status st = core_csv_read(in, path ? path : "stdin", t, &err);
  if (in != stdin) fclose(in);
  if (st != NBRDF_OK) return cli_fail_error("eval", &err);
  if (t->n_records == 0) {
    core_csv_free(t);
    return cli_fail("eval", "%s: no header row (see 'nbrdf eval --help')", path ? path : "stdin");
  }
  return CLI_EXIT_OK;
}

int cmd_eval(int argc, char **argv) {
  eval_args a;
  int rc = parse_args(argc, argv, &a);
  if (rc != CLI_EXIT_OK) return rc < 0 ? CLI_EXIT_OK : rc;

  core_csv_table t;
  nbrdf_error err = {0};
  rc = read_input(a.in, &t);
  if (rc != CLI_EXIT_OK) return rc;
  if (a.texture.texture) {
    static char tbuf[1 << 16];
    setvbuf(stdout, tbuf, _IOFBF, sizeof tbuf);
    a.texture.input = a.in ? a.in : "stdin";
    rc = cli_eval_texture(&a.texture, &t, stdout);
    core_csv_free(&t);
    return rc;
  }
  layout lay = {a.in ? a.in : "stdin", 0, {NULL}, {0}};
  batch b = {0};
  rc = find_columns(&t, a.model, &lay);
  if (rc == CLI_EXIT_OK) rc = build_batch(&t, &a, &lay, &b);
  if (rc == CLI_EXIT_OK && b.n > 0 && a.model->neural) {
    const char *columns[MAX_PARAMS];
    for (int p = 0; p < a.model->n_params; p++)
      columns[p] = a.model->params[p].name;
    rc = cli_eval_neural(&a.neural, a.model->neural, b.n, b.params, columns, b.queries, t.line + 1,
                         b.f);
  } else if (rc == CLI_EXIT_OK && b.n > 0 &&
             nbrdf_brdf_eval_many(b.n, b.brdfs, b.queries, &a.options, b.f, b.f_stderr, &err) !=
                 NBRDF_OK)
    rc = cli_fail_error("eval", &err);
  for (size_t k = 0; rc == CLI_EXIT_OK && k < b.n; k++)
    if (!isfinite(b.f[k]) || !isfinite(b.f_stderr[k]))
      rc = cli_fail("eval", "line %zu: the model returned a non-finite value (a bug in nbrdf)",
                    t.line[k + 1]);
  if (rc == CLI_EXIT_OK) {
    static char obuf[1 << 16];
    setvbuf(stdout, obuf, _IOFBF, sizeof obuf);
    write_row(stdout, &t, 0);
    fputs(a.model->stochastic ? ",f,f_stderr\n" : ",f\n", stdout);
    for (size_t k = 0; k < b.n; k++) {
      write_row(stdout, &t, k + 1);
      if (a.model->stochastic)
        printf(",%.17g,%.17g\n", b.f[k], b.f_stderr[k]);
      else
        printf(",%.17g\n", b.f[k]);
    }
    if (fflush(stdout) != 0 || ferror(stdout)) rc = cli_fail("eval", "writing stdout failed");
  }
  batch_free(&b);
  core_csv_free(&t);
  return rc;
}
