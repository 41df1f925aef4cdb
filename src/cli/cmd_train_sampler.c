/* nbrdf train sampler: the sampling network for a decoder run's latents. */
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
#include "cli/cli_progress.h"
#include "cli/cmd_train.h"
#include "core/error.h"
#include "train/samples.h"
#include "train/train_layering.h"
#include "train/train_sampler.h"

/* Appends the latents the layering network gives the data's layered BRDFs
 * (what a bake feeds the sampler), which need not lie where the run's do. */
static nbrdf_status add_layered_latents(const char *layering, const char *tables, int n_data,
                                        const char **data, float **lat, size_t *n,
                                        nbrdf_error *err) {
  train_samples d;
  model_base_table t[2];
  model_layering *net = NULL;
  train_layering_pairs all = {0}, none = {0};
  nbrdf_status st = train_samples_load(n_data, data, &d, err);
  if (st) return st;
  st = cli_train_load_tables(tables, t, err);
  if (!st) st = cli_train_read_net(layering, 1, &net, NULL, err);
  if (!st) st = train_layering_pairs_make(&d, NULL, t, 2, 0, &all, &none, err);
  float *grown = st ? NULL : realloc(*lat, (*n + all.n) * 32 * sizeof(float));
  if (!st && !grown) st = core_fail(err, NBRDF_ERR_MEMORY, "train sampler: out of memory");
  if (grown) *lat = grown;
  if (!st) st = train_layering_pair_latents(net, &all, *lat + *n * 32, err);
  if (!st) *n += all.n;
  train_layering_pairs_free(&all), train_layering_pairs_free(&none);
  model_layering_destroy(net);
  model_base_table_free(&t[0]);
  model_base_table_free(&t[1]);
  train_samples_free(&d);
  return st;
}

typedef struct sampler_args {
  train_sampler_settings s;
  const char *run, *out, *layering, *tables;
  cli_train_list data;
  int brdfs;
  cli_progress_state prog;
  cli_train_limits lim;
} sampler_args;

static void sampler_options(void *args, cli_opt_visit visit, void *user) {
  sampler_args *a = args;
  // clang-format off
  const cli_opt t[] = {
      {.type = CLI_OPT_PATH, .name = "--run", .meta = "DIR", .dest = &a->run,
       .help = "the decoder run (its latents and decoder)"},
      {.type = CLI_OPT_PATH, .name = "--output", .alias = "-o", .meta = "FILE", .dest = &a->out,
       .help = "the sampler.safetensors to write"},
      {.type = CLI_OPT_INT, .name = "--brdfs", .meta = "N", .lo = 0, .hi = 1 << 30,
       .dest = &a->brdfs, .help = "the run's latents used, at most (0: all)"},
      {.type = CLI_OPT_INT, .name = "--epochs", .meta = "N", .lo = 1, .hi = 100000,
       .dest = &a->s.epochs, .help = "epochs of the network's regression (300)"},
      {.type = CLI_OPT_PATH, .name = "--layering", .meta = "F", .dest = &a->layering,
       .help = "also the latents this layering network gives the data's\n"
               "layered BRDFs (with --tables and --data)"},
      {.type = CLI_OPT_PATH, .name = "--tables", .meta = "T", .dest = &a->tables,
       .help = "the base tables (with --layering)"},
      {.type = CLI_OPT_CUSTOM, .name = "--data", .meta = "FILE[,FILE...]", .dest = &a->data,
       .parse = cli_train_read_list, .help = "the data sets (with --layering)"},
      CLI_TRAIN_LIMITS_OPTIONS(&a->lim),
      CLI_PROGRESS_OPTION(&a->prog, "progress as JSON lines on stdout"),
      {0},
  };
  // clang-format on
  visit(user, "sampler", t);
}

static void sampler_args_init(sampler_args *a) {
  memset(a, 0, sizeof *a);
  a->s = (train_sampler_settings)TRAIN_SAMPLER_SETTINGS_DEFAULT;
  a->prog = cli_progress_init(CLI_PROGRESS_COUNT, NULL);
  a->lim = (cli_train_limits)CLI_TRAIN_LIMITS_DEFAULT;
}

void cmd_train_sampler_options(cli_opt_visit visit, void *user) {
  sampler_args a;
  sampler_args_init(&a);
  sampler_options(&a, visit, user);
}

int cmd_train_sampler(int argc, char **argv) {
  sampler_args a;
  sampler_args_init(&a);
  int rc = cli_train_parse("sampler", argc, argv, sampler_options, &a);
  if (rc) {
    free(a.data.copy);
    return rc == CLI_OPTIONS_HELP ? CLI_EXIT_OK : rc;
  }
  train_sampler_settings s = a.s;
  const char *run = a.run, *out = a.out, *layering = a.layering, *tables = a.tables,
             **data = a.data.item;
  char *list = a.data.copy;
  int n_data = a.data.n;
  long brdfs = a.brdfs;
  cli_progress_state prog = a.prog;
  cli_train_limits lim = a.lim;
  if (!run || !out || (layering && (!tables || !n_data)) || (!layering && (tables || n_data))) {
    free(list);
    return cli_usage_error("train", "sampler: --run and -o are required; --layering needs "
                                    "--tables and --data");
  }
  char path[4096], ckpt[4096];
  snprintf(path, sizeof path, "%s/decoder.safetensors", run);
  snprintf(ckpt, sizeof ckpt, "%s/checkpoint.safetensors", run);
  cli_inputs inputs;
  cli_inputs_init(&inputs);
  cli_inputs_add(&inputs, path);
  cli_inputs_add(&inputs, ckpt);
  cli_inputs_add(&inputs, layering);
  cli_inputs_add(&inputs, tables);
  for (int k = 0; k < n_data; k++)
    cli_inputs_add(&inputs, data[k]);
  const char *outputs[2] = {out, lim.checkpoint};
  if (cli_outputs_check("train", &inputs, outputs, 2) != CLI_EXIT_OK) {
    free(list);
    return CLI_EXIT_FAILURE;
  }
  nbrdf_error err = {0};
  model_decoder *dec = NULL;
  model_sampler *net = NULL;
  float *lat = NULL;
  snprintf(path, sizeof path, "%s/decoder.safetensors", run);
  nbrdf_status st = model_decoder_load(path, &dec, &err);
  /* The checkpoint's latents: their count follows from the tensor's size. */
  nn_st_reader *r = NULL;
  snprintf(path, sizeof path, "%s/checkpoint.safetensors", run);
  if (!st) st = nn_st_open(path, &r, &err);
  const nn_st_tensor *t = r ? nn_st_find(r, "latents") : NULL;
  size_t total = t ? t->count / 32 : 0,
         use = brdfs > 0 && (size_t)brdfs < total ? (size_t)brdfs : total;
  if (!st && !t) st = core_fail(&err, NBRDF_ERR_FORMAT, "%s: no latents", path);
  if (!st && !(lat = malloc(use * 32 * sizeof *lat)))
    st = core_fail(&err, NBRDF_ERR_MEMORY, "train sampler: out of memory");
  /* An even spread over the run's BRDFs (single and layered alike). */
  for (size_t k = 0; k < use && !st; k++)
    memcpy(lat + k * 32, t->data + (k * total / use) * 32, 32 * sizeof *lat);
  nn_st_close(r);
  size_t from_run = use;
  if (!st && layering) st = add_layered_latents(layering, tables, n_data, data, &lat, &use, &err);
  train_sampler_result res;
  cli_progress_start(&prog);
  s.progress = cli_progress, s.user = &prog, s.cancel = cli_cancel_flag();
  s.checkpoint = lim.checkpoint, s.checkpoint_seconds = lim.checkpoint_seconds;
  s.max_seconds = lim.max_seconds, s.stop_at_step = lim.stop_at_step;
  cli_cancel_watch();
  if (!st) st = train_sampler_fit(dec, use, lat, &s, &net, &res, &err);
  cli_cancel_unwatch();
  if (!st) st = model_sampler_save(net, out, NULL, &err);
  if (!prog.json) fputc('\n', stderr);
  if (!st)
    printf("train sampler: %zu latents (%zu of the run, %zu from the layering network); "
           "cross-entropy of the fitted proxy %.4f vs cosine %.4f "
           "(lower is closer to the BRDF); network RMS error on raw outputs %.4f\n",
           use, from_run, use - from_run, res.mean_ce_fit, res.mean_ce_cosine, res.rms_o);
  model_sampler_destroy(net);
  model_decoder_destroy(dec);
  free(lat), free(list);
  return st ? cli_fail_error("train", &err) : CLI_EXIT_OK;
}
