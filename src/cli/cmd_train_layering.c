/* nbrdf train layering. */
#include <float.h>
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

typedef struct layering_args {
  train_layering_settings s;
  const char *run, *tables, *out, *decoder, *init;
  int decoded;
  cli_train_list data;
  cli_progress_state prog;
  cli_train_limits lim;
} layering_args;

/* --energy-angles LIST into the energy settings (o->dest). */
static int read_angles(const char *cmd, const cli_opt *o, const char *v) {
  nbrdf_error err = {0};
  if (model_energy_parse_angles(v, o->name, o->dest, &err))
    return cli_usage_error(cmd, "layering: %s", err.message);
  return 0;
}

static void layering_options(void *args, cli_opt_visit visit, void *user) {
  layering_args *a = args;
  // clang-format off
  const cli_opt t[] = {
      {.type = CLI_OPT_CUSTOM, .name = "--data", .meta = "FILE[,FILE...]", .dest = &a->data,
       .parse = cli_train_read_list, .help = "the decoder run's data sets"},
      {.type = CLI_OPT_PATH, .name = "--run", .meta = "DIR", .dest = &a->run,
       .help = "the decoder run (its latents and decoder)"},
      {.type = CLI_OPT_PATH, .name = "--tables", .meta = "FILE", .dest = &a->tables,
       .help = "the base tables"},
      {.type = CLI_OPT_PATH, .name = "--output", .alias = "-o", .meta = "FILE", .dest = &a->out,
       .help = "the layering.safetensors to write"},
      {.type = CLI_OPT_ENUM, .name = "--loss", .choices = "latent|decoded", .dest = &a->decoded,
       .help = "the loss on the latents (default) or through the decoder"},
      {.type = CLI_OPT_PATH, .name = "--decoder", .meta = "FILE", .dest = &a->decoder,
       .help = "decoded loss: the decoder (default: the run's)"},
      {.type = CLI_OPT_PATH, .name = "--init", .meta = "FILE", .dest = &a->init,
       .help = "start from a trained layering network"},
      {.type = CLI_OPT_STRING, .name = "--preset", .choices = "small|medium|paper",
       .dest = &a->s.preset, .help = "the network's size (small)"},
      {.type = CLI_OPT_INT, .name = "--epochs", .meta = "N", .lo = 1, .hi = 1000000,
       .dest = &a->s.epochs, .help = "epochs (400)"},
      {.type = CLI_OPT_INT, .name = "--batch", .meta = "N", .lo = 1, .hi = 65536,
       .dest = &a->s.batch, .help = "pairs per batch (128)"},
      {.type = CLI_OPT_FLOAT, .name = "--lr", .meta = "X", .lo = FLT_MIN, .hi = FLT_MAX,
       .dest = &a->s.lr, .help = "learning rate (1e-3)"},
      {.type = CLI_OPT_INT, .name = "--rows", .meta = "N", .lo = 1, .hi = 65536,
       .dest = &a->s.rows_per_pair, .help = "decoded loss: samples per BRDF per step (64)"},
      {.type = CLI_OPT_INT, .name = "--decay-every", .meta = "EPOCHS", .lo = 0, .hi = 1000000,
       .dest = &a->s.decay_every, .help = "epochs between learning-rate halvings (150)"},
      {.type = CLI_OPT_U64, .name = "--seed", .meta = "S", .hi = 2147483647.0, .dest = &a->s.seed,
       .help = "seed (1)"},
      {.type = CLI_OPT_PATH, .name = "--log", .meta = "CSV", .dest = &a->s.log_path,
       .help = "the training log"},
      {.type = CLI_OPT_FLOAT, .name = "--energy", .meta = "LAMBDA", .lo = 0, .hi = 1e6,
       .dest = &a->s.energy.lambda, .help = "decoded loss: the energy penalty's weight (0: off)"},
      {.type = CLI_OPT_CUSTOM, .name = "--energy-angles", .meta = "LIST", .dest = &a->s.energy,
       .parse = read_angles,
       .help = "the penalty's incidence angles in degrees\n(0,40,60,75,85,89)"},
      {.type = CLI_OPT_INT, .name = "--energy-brdfs", .meta = "K", .lo = 1, .hi = 4096,
       .dest = &a->s.energy_brdfs, .help = "pairs penalised per batch (8)"},
      {.type = CLI_OPT_FLOAT, .name = "--energy-floor", .meta = "M", .lo = 0, .hi = 1,
       .dest = &a->s.energy.floor_margin,
       .help = "also penalise decoded albedo below the truth's\n− 2 standard errors − M (off unless given)"},
      CLI_TRAIN_LIMITS_OPTIONS(&a->lim),
      CLI_PROGRESS_OPTION(&a->prog, "progress as JSON lines on stdout"),
      {0},
  };
  // clang-format on
  visit(user, "layering", t);
}

static void layering_args_init(layering_args *a) {
  memset(a, 0, sizeof *a);
  a->s = (train_layering_settings)TRAIN_LAYERING_SETTINGS_DEFAULT;
  a->prog = cli_progress_init(CLI_PROGRESS_COUNT, NULL);
  a->lim = (cli_train_limits)CLI_TRAIN_LIMITS_DEFAULT;
}

void cmd_train_layering_options(cli_opt_visit visit, void *user) {
  layering_args a;
  layering_args_init(&a);
  layering_options(&a, visit, user);
}

int cmd_train_layering(int argc, char **argv) {
  layering_args a;
  layering_args_init(&a);
  int rc = cli_train_parse("layering", argc, argv, layering_options, &a);
  if (rc) {
    free(a.data.copy);
    return rc == CLI_OPTIONS_HELP ? CLI_EXIT_OK : rc;
  }
  train_layering_settings s = a.s;
  const char *run = a.run, *tables = a.tables, *out = a.out, **data = a.data.item,
             *decoder = a.decoder, *init = a.init;
  int decoded = a.decoded, n_data = a.data.n;
  char *list = a.data.copy;
  cli_progress_state prog = a.prog;
  cli_train_limits lim = a.lim;
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
