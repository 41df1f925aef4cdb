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
#include "cli/cli_progress.h"
#include "cli/cli_outputs.h"
#include "train/dataset.h"

void cmd_dataset_usage(FILE *out) {
  fprintf(out,
          "usage: nbrdf dataset --out FILE --kind KIND --count N --seed S [--incident K]\n"
          "                     [--outgoing M] [--sampled S] [--spp N] [--threads T]\n"
          "                     [--draws table2|coverage]\n"
          "                     [--progress=json]\n"
          "       nbrdf dataset --check FILE\n"
          "\n"
          "Writes ground-truth training data for BRDFs drawn from the paper's Table 2\n"
          "(docs/DATASET.md). The output depends only on the settings, never on --threads.\n"
          "An existing FILE with the same settings is resumed (Ctrl-C stops cleanly; run\n"
          "the same command again to continue).\n"
          "\n"
          "options:\n"
          "  --kind KIND      conductor, dielectric, single (half each), layered2, layered3\n"
          "  --count N        BRDFs to draw\n"
          "  --draws D        table2 (default): the paper's Table 2; coverage: more low-IOR\n"
          "                   coats (eta = 1 5 %%, eta in [1, 1.2] 20 %%) and sharp coats\n"
          "                   (alpha <= 0.03 15 %%) (docs/DATASET.md)\n"
          "  --seed S         unsigned 64-bit seed (held-out sets use another seed family)\n"
          "  --incident K     incident directions per BRDF, θi stratified over [0, 89°) (8)\n"
          "  --outgoing M     outgoing directions per incident direction (128)\n"
          "  --sampled S      of which importance-sampled from the BRDF (default M/2)\n"
          "  --spp N          layered: whole-lobe random walks per incident direction (2048)\n"
          "  --threads T      0 = all cores (default)\n"
          "  --progress=json  progress as JSON lines on stdout instead of text on stderr\n"
          "  --check FILE     validate FILE (checksums, parameters, samples); print a summary\n");
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
  train_dataset_settings s = TRAIN_DATASET_SETTINGS_DEFAULT;
  const char *out = NULL, *check = NULL;
  int have_kind = 0, have_count = 0, have_seed = 0, have_sampled = 0;
  cli_progress_state prog = cli_progress_init(CLI_PROGRESS_RATE, "BRDFs");
  for (int i = 1; i < argc; i++) {
    const char *v;
    long n;
    if ((v = cli_option_value(argc, argv, &i, "--out"))) {
      out = v;
    } else if ((v = cli_option_value(argc, argv, &i, "--check"))) {
      check = v;
    } else if ((v = cli_option_value(argc, argv, &i, "--kind"))) {
      int k = train_kind_parse(v);
      if (k < 0)
        return cli_usage_error("dataset",
                               "unknown kind '%s' (expected conductor, dielectric, "
                               "single, layered2 or layered3)",
                               v);
      s.kind = (train_kind)k, have_kind = 1;
    } else if ((v = cli_option_value(argc, argv, &i, "--draws"))) {
      int d = train_draws_parse(v);
      if (d < 0)
        return cli_usage_error("dataset", "unknown --draws '%s' (expected table2 or coverage)", v);
      s.draws = (train_draws)d;
    } else if ((v = cli_option_value(argc, argv, &i, "--count"))) {
      if (!cli_parse_u64(v, &s.count) || s.count < 1)
        return cli_usage_error("dataset", "--count '%s' is not a positive integer", v);
      have_count = 1;
    } else if ((v = cli_option_value(argc, argv, &i, "--seed"))) {
      if (!cli_parse_u64(v, &s.seed))
        return cli_usage_error("dataset", "--seed '%s' is not an unsigned 64-bit integer", v);
      have_seed = 1;
    } else if ((v = cli_option_value(argc, argv, &i, "--incident"))) {
      if (!cli_parse_int(v, 1, 4096, &n))
        return cli_usage_error("dataset", "--incident '%s' is not an integer in [1, 4096]", v);
      s.incident = (int)n;
    } else if ((v = cli_option_value(argc, argv, &i, "--outgoing"))) {
      if (!cli_parse_int(v, 1, 65536, &n))
        return cli_usage_error("dataset", "--outgoing '%s' is not an integer in [1, 65536]", v);
      s.outgoing = (int)n;
    } else if ((v = cli_option_value(argc, argv, &i, "--sampled"))) {
      if (!cli_parse_int(v, 0, 65536, &n))
        return cli_usage_error("dataset", "--sampled '%s' is not an integer in [0, 65536]", v);
      s.sampled = (int)n, have_sampled = 1;
    } else if ((v = cli_option_value(argc, argv, &i, "--spp"))) {
      if (!cli_parse_int(v, 2, 1L << 30, &n))
        return cli_usage_error("dataset", "--spp '%s' is not an integer in [2, 2^30]", v);
      s.spp = (int)n;
    } else if ((v = cli_option_value(argc, argv, &i, "--threads"))) {
      if (!cli_parse_int(v, 0, 4096, &n))
        return cli_usage_error("dataset", "--threads '%s' is not an integer in [0, 4096]", v);
      s.threads = (int)n;
    } else if (cli_progress_flag(argv[i], &prog)) {
    } else if (cli_is_help(argv[i])) {
      cmd_dataset_usage(stdout);
      return CLI_EXIT_OK;
    } else {
      return cli_usage_error("dataset", "unexpected argument '%s'", argv[i]);
    }
  }
  if (check) {
    if (out) return cli_usage_error("dataset", "--check and --out exclude each other");
    return run_check(check);
  }
  if (!out || !*out) return cli_usage_error("dataset", "--out is required (or --check FILE)");
  if (!have_kind || !have_count || !have_seed)
    return cli_usage_error("dataset", "--kind, --count and --seed are required");
  if (!have_sampled) s.sampled = s.outgoing / 2;
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
