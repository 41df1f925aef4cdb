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

int cmd_train_sampler(int argc, char **argv) {
  train_sampler_settings s = TRAIN_SAMPLER_SETTINGS_DEFAULT;
  const char *run = NULL, *out = NULL, *layering = NULL, *tables = NULL, *data[64];
  char *list = NULL;
  int n_data = 0;
  long brdfs = 0, n;
  cli_progress_state prog = cli_progress_init(CLI_PROGRESS_COUNT, NULL);
  cli_train_limits lim = CLI_TRAIN_LIMITS_DEFAULT;
  for (int i = 2; i < argc; i++) {
    const char *v;
    int code;
    if (cli_train_limits_option(argc, argv, &i, &lim, &code)) {
      if (code) {
        free(list);
        return code;
      }
    } else if ((v = cli_option_value(argc, argv, &i, "--run")))
      run = v;
    else if ((v = cli_option_value(argc, argv, &i, "-o")))
      out = v;
    else if ((v = cli_option_value(argc, argv, &i, "--layering")))
      layering = v;
    else if ((v = cli_option_value(argc, argv, &i, "--tables")))
      tables = v;
    else if ((v = cli_option_value(argc, argv, &i, "--data"))) {
      free(list);
      list = strdup(v);
      n_data = list ? cli_train_split_list(list, data, 64) : 0;
    } else if ((v = cli_option_value(argc, argv, &i, "--brdfs")) &&
               cli_parse_int(v, 0, 1L << 30, &n))
      brdfs = n;
    else if ((v = cli_option_value(argc, argv, &i, "--epochs")) && cli_parse_int(v, 1, 100000, &n))
      s.epochs = (int)n;
    else if (cli_progress_flag(argv[i], &prog)) {
    } else {
      free(list);
      return cli_usage_error("train", "sampler: unexpected or invalid argument '%s'", argv[i]);
    }
  }
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
