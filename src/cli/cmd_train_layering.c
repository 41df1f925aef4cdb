/* nbrdf train layering / nbrdf train bundle. */
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
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
  cli_train_progress prog = {0, 0};
  cli_train_limits lim = CLI_TRAIN_LIMITS_DEFAULT;
  for (int i = 2; i < argc; i++) {
    const char *v;
    long n;
    double x;
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
    else if ((v = cli_option_value(argc, argv, &i, "--lr")) && cli_parse_double(v, &x) && x > 0)
      s.lr = (float)x;
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
    } else if (!strcmp(argv[i], "--progress=json"))
      prog.json = 1;
    else {
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
  s.progress = cli_train_on_progress, s.user = &prog, s.cancel = cli_cancel_flag();
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

int cmd_train_bundle(int argc, char **argv) {
  const char *out = NULL, *name = "default", *decoder = NULL, *tables = NULL, *layering = NULL,
             *sampler = NULL, *card = NULL, *note = NULL;
  for (int i = 2; i < argc; i++) {
    const char *v;
    if ((v = cli_option_value(argc, argv, &i, "-o")))
      out = v;
    else if ((v = cli_option_value(argc, argv, &i, "--name")))
      name = v;
    else if ((v = cli_option_value(argc, argv, &i, "--decoder")))
      decoder = v;
    else if ((v = cli_option_value(argc, argv, &i, "--tables")))
      tables = v;
    else if ((v = cli_option_value(argc, argv, &i, "--layering")))
      layering = v;
    else if ((v = cli_option_value(argc, argv, &i, "--sampler")))
      sampler = v;
    else if ((v = cli_option_value(argc, argv, &i, "--card")))
      card = v;
    else if ((v = cli_option_value(argc, argv, &i, "--note")))
      note = v;
    else
      return cli_usage_error("train", "bundle: unexpected argument '%s'", argv[i]);
  }
  if (!out || !decoder || !tables || !layering)
    return cli_usage_error("train", "bundle: -o, --decoder, --tables and --layering are required");
  cli_inputs inputs;
  cli_inputs_init(&inputs);
  const char *read[5] = {decoder, tables, layering, sampler, card};
  for (int k = 0; k < 5; k++)
    cli_inputs_add(&inputs, read[k]);
  if (cli_outputs_check_bundle("train", &inputs, out) != CLI_EXIT_OK) return CLI_EXIT_FAILURE;
  nbrdf_error err = {0};
  model_decoder *dec = NULL;
  model_layering *lay = NULL;
  model_sampler *smp = NULL;
  model_base_table t[2];
  char *card_text = NULL;
  nbrdf_status st = model_decoder_load(decoder, &dec, &err);
  if (!st) st = cli_train_load_tables(tables, t, &err);
  if (!st) st = cli_train_read_net(layering, 1, &lay, NULL, &err);
  /* Without a trained sampler the proxy keeps its initial weights: sampling
   * stays unbiased (MIS), only its variance suffers; the card says so. */
  if (!st)
    st = sampler ? cli_train_read_net(sampler, 0, NULL, &smp, &err)
                 : model_sampler_create("default", 32, 1, &smp, &err);
  size_t card_size = 0;
  if (!st && card) st = model_read_file(card, MODEL_JSON_MAX, &card_text, &card_size, &err);
  uint64_t sum = 0;
  if (!st) {
    model_bundle_parts parts = {.name = name,
                                .trained = 1,
                                .seed = 1,
                                .note = note,
                                .card = card_text,
                                .decoder = dec,
                                .layering = lay,
                                .sampler = smp,
                                .tables = {&t[0], &t[1]}};
    st = model_bundle_save(out, &parts, &sum, &err);
  }
  model_decoder_destroy(dec);
  model_layering_destroy(lay);
  model_sampler_destroy(smp);
  model_base_table_free(&t[0]);
  model_base_table_free(&t[1]);
  free(card_text);
  if (st) return cli_fail_error("train", &err);
  printf("train bundle: %s (checksum %016llx)\n", out, (unsigned long long)sum);
  return CLI_EXIT_OK;
}
