/* nbrdf dataset: generates (or resumes) a training data set, or checks one.
 * The format is docs/DATASET.md; the generator is src/train/dataset.h. */
#include <inttypes.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
#include "cli/cli_progress.h"
#include "train/dataset.h"

typedef struct dataset_args {
  train_dataset_settings s;
  const char *out, *check;
  int have_kind, have_count, have_seed, have_sampled;
  cli_progress_state prog;
} dataset_args;

static void dataset_options(dataset_args *a, cli_opt_visit visit, void *user) {
  static const int kinds[] = {TRAIN_CONDUCTOR, TRAIN_DIELECTRIC, TRAIN_SINGLE, TRAIN_LAYERED2,
                              TRAIN_LAYERED3};
  // clang-format off
  const cli_opt t[] = {
      {.type = CLI_OPT_PATH, .name = "--out", .meta = "FILE", .dest = &a->out,
       .help = "the data set to write, or resume"},
      {.type = CLI_OPT_ENUM, .name = "--kind", .meta = "KIND",
       .choices = "conductor|dielectric|single|layered2|layered3", .values = kinds,
       .dest = &a->s.kind, .seen = &a->have_kind,
       .help = "conductor, dielectric, single (half each), layered2, layered3"},
      {.type = CLI_OPT_U64, .name = "--count", .meta = "N", .lo = 1, .dest = &a->s.count,
       .seen = &a->have_count, .help = "BRDFs to draw"},
      {.type = CLI_OPT_ENUM, .name = "--draws", .meta = "D", .choices = "table2|coverage|tails|mirror",
       .dest = &a->s.draws,
       .help = "table2 (default): the paper's Table 2; coverage: more low-IOR\n"
               "coats (eta = 1 5 %, eta in [1, 1.2] 20 %) and sharp coats\n"
               "(alpha <= 0.03 15 %); tails: only low-IOR (eta <= 1.2) and sharp\n"
               "(alpha <= 0.05) coats, a third each and both; mirror: smooth\n"
               "bright bases (alpha2 0.01-0.05, r0 0.8-1) under any coat (docs/DATASET.md)"},
      {.type = CLI_OPT_U64, .name = "--seed", .meta = "S", .dest = &a->s.seed,
       .seen = &a->have_seed,
       .help = "unsigned 64-bit seed (held-out sets use another seed family)"},
      {.type = CLI_OPT_INT, .name = "--incident", .meta = "K", .lo = 1, .hi = 4096,
       .dest = &a->s.incident,
       .help = "incident directions per BRDF, θi stratified over [0, 89°) (8)"},
      {.type = CLI_OPT_INT, .name = "--outgoing", .meta = "M", .lo = 1, .hi = 65536,
       .dest = &a->s.outgoing, .help = "outgoing directions per incident direction (128)"},
      {.type = CLI_OPT_INT, .name = "--sampled", .meta = "S", .lo = 0, .hi = 65536,
       .dest = &a->s.sampled, .seen = &a->have_sampled,
       .help = "of which importance-sampled from the BRDF (default M/2)"},
      {.type = CLI_OPT_INT, .name = "--spp", .meta = "N", .lo = 2, .hi = 1 << 30, .dest = &a->s.spp,
       .help = "layered: whole-lobe random walks per incident direction (2048)"},
      {.type = CLI_OPT_INT, .name = "--threads", .meta = "T", .lo = 0, .hi = 4096,
       .dest = &a->s.threads, .help = "0 = all cores (default)"},
      CLI_PROGRESS_OPTION(&a->prog, "progress as JSON lines on stdout instead of text on stderr"),
      {.type = CLI_OPT_PATH, .name = "--check", .meta = "FILE", .dest = &a->check,
       .help = "validate FILE (checksums, parameters, samples); print a summary"},
      {0},
  };
  // clang-format on
  visit(user, NULL, t);
}

static void dataset_args_init(dataset_args *a) {
  memset(a, 0, sizeof *a);
  a->s = (train_dataset_settings)TRAIN_DATASET_SETTINGS_DEFAULT;
  a->prog = cli_progress_init(CLI_PROGRESS_RATE, "BRDFs");
}

void cmd_dataset_options(cli_opt_visit visit, void *user) {
  dataset_args a;
  dataset_args_init(&a);
  dataset_options(&a, visit, user);
}

void cmd_dataset_usage(FILE *out) {
  fprintf(out, "usage: nbrdf dataset --out FILE --kind KIND --count N --seed S [--incident K]\n"
               "                     [--outgoing M] [--sampled S] [--spp N] [--threads T]\n"
               "                     [--draws table2|coverage|tails|mirror]\n"
               "                     [--progress=json]\n"
               "       nbrdf dataset --check FILE\n"
               "\n"
               "Writes ground-truth training data for BRDFs drawn from the paper's Table 2\n"
               "(docs/DATASET.md). The output depends only on the settings, never on --threads.\n"
               "An existing FILE with the same settings is resumed (Ctrl-C stops cleanly; run\n"
               "the same command again to continue).\n"
               "\n"
               "options:\n");
  cmd_dataset_options(cli_options_help_visit, out);
}

typedef struct check_stats {
  uint64_t samples, sampled_kinds[5];
  double sum_f, max_f, sum_rel_se;
  uint64_t n_rel;
} check_stats;

static int on_record(void *user, const train_dataset_record *r) {
  check_stats *c = user;
  c->sampled_kinds[r->params.kind]++;
  for (size_t j = 0; j < r->n_samples; j++) {
    const float *x = r->samples + TRAIN_DATASET_FLOATS * j;
    c->samples++;
    c->sum_f += x[6];
    if (x[6] > c->max_f) c->max_f = x[6];
    if (x[6] > 0.0f) c->sum_rel_se += (double)x[7] / x[6], c->n_rel++;
  }
  return 0;
}

static int run_check(const char *path) {
  train_dataset_info info;
  check_stats c;
  memset(&c, 0, sizeof c);
  nbrdf_error err = {0};
  if (train_dataset_read(path, 1, &info, on_record, &c, &err) != NBRDF_OK)
    return cli_fail_error("dataset", &err);
  const train_dataset_settings *s = &info.settings;
  printf("file: %s\nstatus: valid, complete\nchecksum: %016" PRIx64 "\n", path, info.checksum);
  printf("kind: %s\ndraws: %s\ncount: %" PRIu64 "\nseed: %" PRIu64 "\n", train_kind_name(s->kind),
         train_draws_name(s->draws), s->count, s->seed);
  printf("incident: %d\noutgoing: %d\nsampled: %d\nspp: %d\n", s->incident, s->outgoing, s->sampled,
         s->spp);
  printf("conductors: %" PRIu64 "\ndielectrics: %" PRIu64 "\nlayered2: %" PRIu64
         "\nlayered3: %" PRIu64 "\n",
         c.sampled_kinds[0], c.sampled_kinds[1], c.sampled_kinds[2], c.sampled_kinds[3]);
  printf("samples: %" PRIu64 "\nmean_f: %.6g\nmax_f: %.6g\nmean_relative_stderr: %.4g\n", c.samples,
         c.samples ? c.sum_f / (double)c.samples : 0.0, c.max_f,
         c.n_rel ? c.sum_rel_se / (double)c.n_rel : 0.0);
  return CLI_EXIT_OK;
}

int cmd_dataset(int argc, char **argv) {
  dataset_args a;
  dataset_args_init(&a);
  cli_parse_call call = {"dataset", NULL, argc, 1, argv, NULL, 0};
  dataset_options(&a, cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) {
    cmd_dataset_usage(stdout);
    return CLI_EXIT_OK;
  }
  if (call.rc != CLI_OPTIONS_OK) return call.rc;
  train_dataset_settings s = a.s;
  const char *out = a.out, *check = a.check;
  cli_progress_state prog = a.prog;
  if (check) {
    if (out) return cli_usage_error("dataset", "--check and --out exclude each other");
    return run_check(check);
  }
  if (!out || !*out) return cli_usage_error("dataset", "--out is required (or --check FILE)");
  if (!a.have_kind || !a.have_count || !a.have_seed)
    return cli_usage_error("dataset", "--kind, --count and --seed are required");
  if (!a.have_sampled) s.sampled = s.outgoing / 2;
  if (s.sampled > s.outgoing)
    return cli_usage_error("dataset", "--sampled %d exceeds --outgoing %d", s.sampled, s.outgoing);
  cli_inputs none; /* generated, nothing read; the output is still checked */
  cli_inputs_init(&none);
  if (cli_output_check("dataset", &none, out) != CLI_EXIT_OK) return CLI_EXIT_FAILURE;
  s.progress = cli_progress, s.user = &prog;
  cli_progress_start(&prog);
  cli_cancel_watch();
  uint64_t resumed = 0;
  nbrdf_error err = {0};
  nbrdf_status st = train_dataset_write(out, &s, &resumed, &err);
  cli_cancel_unwatch();
  if (st != NBRDF_OK) return cli_fail_error("dataset", &err);
  double t = cli_progress_seconds(&prog);
  uint64_t made = s.count - resumed;
  double per = (double)s.incident * s.outgoing;
  fprintf(stderr,
          "dataset: %s complete: %" PRIu64 " BRDFs (%" PRIu64 " resumed), %" PRIu64
          " new in %.2f s: %.4g BRDFs/s, %.4g samples/s\n",
          out, s.count, resumed, made, t, t > 0 ? made / t : 0.0, t > 0 ? made * per / t : 0.0);
  return CLI_EXIT_OK;
}
