/* nbrdf train layering. */
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
#include "cli/cli_progress.h"
#include "cli/cmd_train.h"
#include "core/error.h"
#include "model/bundle.h"
#include "model/files.h"
#include "train/train_layering.h"

int cmd_train_layering(int argc, char **argv) {
  train_layering_settings s = TRAIN_LAYERING_SETTINGS_DEFAULT;
  const char *run = NULL, *tables = NULL, *out = NULL, *data[64], *decoder = NULL, *init = NULL;
  int decoded = 0;
  char *list = NULL;
  int n_data = 0;
  cli_progress_state prog = cli_progress_init(CLI_PROGRESS_COUNT, NULL);
  cli_train_limits lim = CLI_TRAIN_LIMITS_DEFAULT;
  for (int i = 2; i < argc; i++) {
    const char *v;
    long n;
    double x;
    float f;
    int code;
    if (cli_train_limits_option(argc, argv, &i, &lim, &code)) {
      if (code) {
        free(list);
        return code;
      }
    } else if ((v = cli_option_value(argc, argv, &i, "--data"))) {
      free(list);
      list = strdup(v);
      n_data = list ? cli_train_split_list(list, data, 64) : 0;
    } else if ((v = cli_option_value(argc, argv, &i, "--run")))
      run = v;
    else if ((v = cli_option_value(argc, argv, &i, "--tables")))
      tables = v;
    else if ((v = cli_option_value(argc, argv, &i, "--decoder")))
      decoder = v;
    else if ((v = cli_option_value(argc, argv, &i, "--init")))
      init = v;
    else if ((v = cli_option_value(argc, argv, &i, "--loss")) &&
             (!strcmp(v, "latent") || !strcmp(v, "decoded")))
      decoded = !strcmp(v, "decoded");
    else if ((v = cli_option_value(argc, argv, &i, "--rows")) && cli_parse_int(v, 1, 65536, &n))
      s.rows_per_pair = (int)n;
    else if ((v = cli_option_value(argc, argv, &i, "-o")))
      out = v;
    else if ((v = cli_option_value(argc, argv, &i, "--preset")))
      s.preset = v;
    else if ((v = cli_option_value(argc, argv, &i, "--log")))
      s.log_path = v;
    else if ((v = cli_option_value(argc, argv, &i, "--epochs")) && cli_parse_int(v, 1, 1000000, &n))
      s.epochs = (int)n;
    else if ((v = cli_option_value(argc, argv, &i, "--batch")) && cli_parse_int(v, 1, 65536, &n))
      s.batch = (int)n;
    else if ((v = cli_option_value(argc, argv, &i, "--decay-every")) &&
             cli_parse_int(v, 0, 1000000, &n))
      s.decay_every = (int)n;
    else if ((v = cli_option_value(argc, argv, &i, "--seed")) &&
             cli_parse_int(v, 0, 2147483647, &n))
      s.seed = (uint64_t)n;
    else if ((v = cli_option_value(argc, argv, &i, "--lr")) && cli_parse_float(v, &f) && f > 0)
      s.lr = f;
    else if ((v = cli_option_value(argc, argv, &i, "--energy")) && cli_parse_double(v, &x) &&
             x >= 0 && x <= 1e6)
      s.energy.lambda = (float)x;
    else if ((v = cli_option_value(argc, argv, &i, "--energy-brdfs")) &&
             cli_parse_int(v, 1, 4096, &n))
      s.energy_brdfs = (int)n;
    else if ((v = cli_option_value(argc, argv, &i, "--energy-angles"))) {
      nbrdf_error e2 = {0};
      if (model_energy_parse_angles(v, "--energy-angles", &s.energy, &e2)) {
        free(list);
        return cli_usage_error("train", "layering: %s", e2.message);
      }
    } else if (cli_progress_flag(argv[i], &prog)) {
    } else {
      free(list);
      return cli_usage_error("train", "layering: unexpected or invalid argument '%s'", argv[i]);
    }
  }
  if (!n_data || !tables || !out || (!run && (!decoded || !decoder))) {
    free(list);
    return cli_usage_error("train", "layering: --data, --tables, -o and --run (or, with --loss "
                                    "decoded, --decoder) are required");
  }
  if (s.energy.lambda > 0.0f && !decoded) {
    free(list);
    return cli_usage_error("train", "layering: --energy needs --loss decoded (the penalty is on "
                                    "decoded albedo)");
  }
  char ckpt[4096], dec_path[4096];
  snprintf(ckpt, sizeof ckpt, "%s/checkpoint.safetensors", run ? run : ".");
  snprintf(dec_path, sizeof dec_path, "%s/decoder.safetensors", run ? run : ".");
  cli_inputs inputs; /* --checkpoint is read and rewritten: resuming is the point */
  cli_inputs_init(&inputs);
  for (int k = 0; k < n_data; k++)
    cli_inputs_add(&inputs, data[k]);
  cli_inputs_add(&inputs, tables);
  cli_inputs_add(&inputs, decoder ? decoder : dec_path);
  cli_inputs_add(&inputs, init);
  if (!decoded) cli_inputs_add(&inputs, ckpt);
  s.checkpoint = lim.checkpoint, s.checkpoint_seconds = lim.checkpoint_seconds;
  s.max_seconds = lim.max_seconds, s.stop_at_step = lim.stop_at_step;
  const char *outputs[3] = {out, s.log_path, s.checkpoint};
  if (cli_outputs_check("train", &inputs, outputs, 3) != CLI_EXIT_OK) {
    free(list);
    return CLI_EXIT_FAILURE;
  }
  nbrdf_error err = {0};
  train_samples d;
  model_base_table t[2];
  memset(t, 0, sizeof t);
  float *lat = NULL;
  model_layering *net = NULL, *init_net = NULL;
  model_decoder *dec = NULL;
  train_layering_result r = {0};
  nbrdf_status st = train_samples_load(n_data, data, &d, &err);
  if (!st) st = cli_train_load_tables(tables, t, &err);
  if (!st) st = model_decoder_load(decoder ? decoder : dec_path, &dec, &err);
  if (!st && init) st = cli_train_read_net(init, 1, &init_net, NULL, &err);
  if (!st && !decoded && !(lat = malloc(d.n_brdfs * 32 * sizeof *lat)))
    st = core_fail(&err, NBRDF_ERR_MEMORY, "train layering: out of memory");
  if (!st && !decoded) st = train_checkpoint_latents(ckpt, d.n_brdfs, 32, lat, &err);
  cli_progress_start(&prog);
  s.progress = cli_progress, s.user = &prog, s.cancel = cli_cancel_flag();
  s.init = init_net;
  cli_cancel_watch();
  if (!st)
    st = decoded ? train_layering_fit_decoded(&d, dec, t, &s, &net, &r, &err)
                 : train_layering_fit(&d, lat, dec, t, &s, &net, &r, &err);
  cli_cancel_unwatch();
  if (!st) st = model_layering_save(net, out, NULL, &err);
  if (!prog.json) fputc('\n', stderr);
  if (s.checkpoint) cli_train_limits_note(s.checkpoint, r.legacy_resume);
  if (!st && !decoded)
    printf("train layering (latent loss): %zu pairs (%zu held out), train MSE %.5g, validation "
           "MSE %.5g (%.2f %% of the mean squared latent); decoded validation loss %.5g (the "
           "run's own latents: %.5g)\n",
           r.pairs, r.validation_pairs, r.train_loss, r.val_loss,
           100.0 * r.val_loss / (r.target_mean_square > 0 ? r.target_mean_square : 1),
           r.val_decoded, r.val_decoded_oracle);
  if (!st && decoded)
    printf("train layering (decoded loss): %zu pairs (%zu held out), epochs %d (resumed at %d), "
           "train loss %.5g, decoded validation loss %.5g\n",
           r.pairs, r.validation_pairs, r.epochs_done, r.resumed_from, r.train_loss, r.val_decoded);
  model_layering_destroy(net);
  model_layering_destroy(init_net);
  model_decoder_destroy(dec);
  model_base_table_free(&t[0]);
  model_base_table_free(&t[1]);
  free(lat), free(list);
  train_samples_free(&d);
  return st ? cli_fail_error("train", &err) : CLI_EXIT_OK;
}
