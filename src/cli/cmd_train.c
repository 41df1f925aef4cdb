/* nbrdf train: the training loops of src/train (checkpointed, resumable). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
#include "cli/cli_progress.h"
#include "cli/cmd_train.h"
#include "train/train_decoder.h"

static void print_table(void *user, const char *sub, const cli_opt *table);
void cmd_train_options(cli_opt_visit visit, void *user);

void cmd_train_usage(FILE *out) {
  fprintf(
      out,
      "usage: nbrdf train decoder --data FILE[,FILE...] --run DIR [options]\n"
      "       nbrdf train tables --decoder FILE -o FILE [--alpha-nodes N] [--eta-nodes N]\n"
      "                          [--r0-nodes N] [--eta-warp P] [--r0-warp P] [--eta-min E]\n"
      "                          [--steps N] [--seed S] [trainer flags]\n"
      "       nbrdf train layering --data FILE[,...] --run DIR --tables FILE -o FILE\n"
      "                          [--loss latent|decoded] [--decoder FILE] [--init FILE]\n"
      "                          [--preset small|medium|paper] [--epochs N] [--batch N] [--lr X]\n"
      "                          [--rows N] [--decay-every EPOCHS] [--seed S] [--log CSV]\n"
      "                          [--energy LAMBDA [--energy-angles LIST]\n"
      "                          [--energy-brdfs K (8 pairs per batch)]\n"
      "                          [--energy-floor M]] (decoded loss)\n"
      "                          [trainer flags]\n"
      "       nbrdf train sampler --run DIR -o FILE [--brdfs N] [--epochs N]\n"
      "                          [--layering F --tables T --data FILE[,...]] [trainer flags]\n"
      "       nbrdf train bundle -o DIR --decoder F --tables F --layering F [--sampler F]\n"
      "                          [--name NAME] [--card MODEL_CARD.md] [--note TEXT]\n"
      "                          [--reads-textures-of OLD_DIR]\n"
      "\n"
      "Auto-decoder training (paper §3.2): decoder weights and one latent per training\n"
      "BRDF learned together. DIR holds checkpoint.safetensors (resume: run the same\n"
      "command again), decoder.safetensors and log.csv. Ctrl-C (SIGTERM, SIGHUP)\n"
      "checkpoints and stops. --init-bundle DIR fine-tunes a bundle's decoder: its\n"
      "weights, and each BRDF's latent as the bundle gives its parameters (tables and\n"
      "layering network), are where the run starts; retrain the tables and layering\n"
      "network through the new decoder afterwards (scripts/train-tails.sh).\n"
      "\n"
      "A checkpoint records the settings a resume must share (nbrdf.options): another\n"
      "value is refused, naming the setting and both values.\n"
      "\n"
      "The trainer flags (--checkpoint, --checkpoint-minutes, --minutes, --stop-at-step) are\n"
      "those of tables, layering and sampler: one trainer runs every fit; a step is a\n"
      "projection step, a batch of pairs, a batch of latents.\n"
      "\n"
      "tables: projects the analytic base BRDFs (top dielectric over (alpha1, eta), bottom\n"
      "conductor over (alpha2, r0)) on a grid with the decoder frozen and writes\n"
      "base_tables.safetensors (defaults: 16 alpha x 8 eta, 16 alpha x 9 r0, 800 steps).\n"
      "eta nodes E + (2 - E) u^P (E = --eta-min, 1.05; 1 lets a bake take eta = 1, no coat,\n"
      "without clamping), r0 nodes u^P (u uniform; P = 1 default, 2 is denser at the\n"
      "dim end and measured better: docs/TRAINING.md, 'Base tables').\n"
      "layering: inputs from the tables as a bake looks them up. --loss latent (default):\n"
      "fits the latents a decoder run learned for its two-layer BRDFs (--data: the same\n"
      "files as that run). --loss decoded: the decoder (--decoder, or the run's) frozen,\n"
      "the loss is its own on the decoded values against every two-layer BRDF's samples\n"
      "(--rows samples per BRDF per step, 64); --init starts from a trained layering\n"
      "network. Both losses resume exactly from --checkpoint.\n"
      "sampler: per-latent proxy (sigma, w) by cross-entropy against the decoded BRDF,\n"
      "then the sampling network regressed on them (src/train/train_sampler.h). With\n"
      "--layering, the latents that network gives the data's layered BRDFs join the\n"
      "run's: they are what a bake feeds the sampler.\n"
      "bundle: assembles a model bundle; without --sampler the proxy network keeps its\n"
      "initial weights (and the card must say so). --reads-textures-of OLD_DIR: the new\n"
      "bundle also reads textures baked with OLD_DIR (and those OLD_DIR reads); refused\n"
      "unless both decoder.safetensors are the same bytes (a texture decodes with its\n"
      "bundle's decoder, so a retrained layering network or tables keep old textures).\n"
      "Then `nbrdf bundle audit-slopes DIR` measures the energy audit's slopes for the new\n"
      "weights (without them a bake measures every distinct tuple's albedo).\n");
  cmd_train_options(print_table, out);
}

typedef struct decoder_args {
  train_decoder_settings s;
  cli_train_list data;
  const char *preset, *encoding, *output, *init_bundle;
  double steps, minutes, rows, lrw, lrl, l2, decay, gamma, seed, ckpt, nval, width, blocks, octaves,
      bweight, stop_at, energy, energy_brdfs, energy_floor;
  cli_progress_state prog;
} decoder_args;

static int read_loss(const char *cmd, const cli_opt *o, const char *v) {
  if (!model_loss_parse(v, o->dest)) return cli_opt_bad(cmd, o->name, "l1-log1p or l1", v);
  return 0;
}

static int read_angles(const char *cmd, const cli_opt *o, const char *v) {
  nbrdf_error err = {0};
  if (model_energy_parse_angles(v, o->name, o->dest, &err))
    return cli_usage_error(cmd, "%s", err.message);
  return 0;
}

#define NUM(flag, m, l, h, field, text)                                                            \
  {                                                                                                \
    .type = CLI_OPT_DOUBLE, .name = flag, .meta = m, .lo = l, .hi = h, .dest = &a->field,          \
    .help = text                                                                                   \
  }

static void decoder_options(void *args, cli_opt_visit visit, void *user) {
  decoder_args *a = args;
  // clang-format off
  const cli_opt t[] = {
      {.type = CLI_OPT_CUSTOM, .name = "--data", .meta = "FILE[,FILE...]", .dest = &a->data,
       .parse = cli_train_read_list, .help = "the data sets (nbrdf dataset)"},
      {.type = CLI_OPT_PATH, .name = "--run", .meta = "DIR", .dest = &a->s.run_dir,
       .help = "the run's folder: checkpoint, decoder, log"},
      {.type = CLI_OPT_PATH, .name = "--init-bundle", .meta = "DIR", .dest = &a->init_bundle,
       .help = "fine-tune: start from this bundle's decoder (its architecture)\n"
               "and the latents it gives each BRDF's parameters"},
      {.help = "architecture (a preset, or your own residual MLP):"},
      {.type = CLI_OPT_STRING, .name = "--preset", .meta = "NAME",
       .choices = "paper|large|medium|small", .dest = &a->preset,
       .help = "paper, large, medium (default), small"},
      NUM("--width", "W", 1, 4096, width, "residual MLP width (with --blocks; default 64)"),
      NUM("--blocks", "B", 1, 64, blocks, "residual blocks (default 3)"),
      {.type = CLI_OPT_STRING, .name = "--encoding", .choices = "cartesian|halfdiff",
       .dest = &a->encoding, .help = "the directions' encoding (halfdiff)"},
      NUM("--octaves", "K", 0, MODEL_ENCODING_MAX_OCTAVES, octaves,
          "frequency octaves of the encoding (0)"),
      {.type = CLI_OPT_STRING, .name = "--output", .choices = "f|log1p", .dest = &a->output,
       .help = "what the network outputs (log1p)"},
      {.help = "training:"},
      NUM("--steps", "N", 1, 1e12, steps,
          "total steps (20000); each step draws --rows-per-brdf samples\nof every BRDF"),
      NUM("--rows-per-brdf", "N", 1, 65536, rows, "samples per BRDF per step (16)"),
      NUM("--minutes", "M", 0, 1e9, minutes,
          "stop (checkpointed) after M minutes of this invocation"),
      NUM("--stop-at-step", "N", 0, 1e12, stop_at,
          "stop (checkpointed) after N steps of the whole run"),
      NUM("--lr-weights", "X", 0, 1, lrw, "learning rate of the weights (2e-3)"),
      NUM("--lr-latent", "X", 0, 10, lrl, "learning rate of the latents (1e-2)"),
      NUM("--latent-l2", "X", 0, 1e3, l2, "L2 penalty on the latents (1e-4)"),
      NUM("--decay-every", "N", 0, 1e9, decay, "steps between learning-rate decays (5000)"),
      NUM("--decay-gamma", "X", 1e-6, 1, gamma, "the decay's factor (0.5)"),
      {.type = CLI_OPT_CUSTOM, .name = "--loss", .choices = "l1-log1p|l1", .dest = &a->s.loss,
       .parse = read_loss, .help = "the loss (l1-log1p)"},
      NUM("--brdf-weight", "P", 0, 2, bweight,
          "weigh BRDF b's loss by max(mean log(1+f), 0.01)^-P (0)"),
      NUM("--seed", "S", 0, 9007199254740992.0, seed, "seed (1)"),
      NUM("--checkpoint-minutes", "M", 1e-3, 1e6, ckpt, "minutes between checkpoints (5)"),
      NUM("--validation", "N", 0, 4096, nval, "held-out BRDFs (24)"),
      NUM("--energy", "LAMBDA", 0, 1e6, energy,
          "(0: off) penalise decoded directional albedo above the ground\n"
          "truth's (+ 2 standard errors + 0.01, at most 1) with weight LAMBDA"),
      {.type = CLI_OPT_CUSTOM, .name = "--energy-angles", .meta = "LIST", .dest = &a->s.energy,
       .parse = read_angles, .help = "the penalty's angles in degrees (0,40,60,75,85,89)"},
      NUM("--energy-brdfs", "K", 1, 4096, energy_brdfs, "BRDFs penalised per step (32)"),
      NUM("--energy-floor", "M", 0, 1, energy_floor,
          "also penalise decoded albedo below the truth's − 2 standard\n"
          "errors − M (two-sided; off unless given)"),
      CLI_PROGRESS_OPTION(&a->prog, "progress as JSON lines on stdout (text on stderr without it)"),
      {0},
  };
  // clang-format on
  visit(user, "decoder", t);
}

static void decoder_args_init(decoder_args *a) {
  memset(a, 0, sizeof *a);
  train_decoder_settings *s = &a->s;
  train_decoder_settings_default(s);
  a->preset = NULL, a->encoding = NULL, a->output = NULL; /* NULL: not given (medium, halfdiff,
                                                              log1p) */
  a->steps = (double)s->steps, a->rows = s->rows_per_brdf, a->lrw = s->lr_weights;
  a->lrl = s->lr_latent, a->l2 = s->latent_l2, a->decay = s->decay_every;
  a->gamma = s->decay_gamma, a->seed = (double)s->seed, a->ckpt = s->checkpoint_seconds / 60.0;
  a->nval = s->validation_brdfs, a->bweight = s->brdf_weight, a->energy = s->energy.lambda;
  a->energy_brdfs = s->energy_brdfs, a->energy_floor = s->energy.floor_margin;
  a->prog = cli_progress_init(CLI_PROGRESS_COUNT, NULL);
}

static void print_table(void *user, const char *sub, const cli_opt *table) {
  fprintf(user, "\n%s options:\n", sub);
  cli_options_help(user, table);
}

void cmd_train_options(cli_opt_visit visit, void *user) {
  decoder_args a;
  decoder_args_init(&a);
  decoder_options(&a, visit, user);
  cmd_train_tables_options(visit, user);
  cmd_train_layering_options(visit, user);
  cmd_train_sampler_options(visit, user);
  cmd_train_bundle_options(visit, user);
}

static int train_decoder(int argc, char **argv) {
  decoder_args a;
  decoder_args_init(&a);
  int rc = cli_train_parse("decoder", argc, argv, decoder_options, &a);
  if (rc) {
    free(a.data.copy);
    return rc == CLI_OPTIONS_HELP ? CLI_EXIT_OK : rc;
  }
  train_decoder_settings s = a.s;
  int arch_given =
      a.preset || a.encoding || a.output || a.width > 0 || a.blocks > 0 || a.octaves > 0;
  const char **data = a.data.item, *preset = a.preset ? a.preset : "medium",
             *encoding = a.encoding ? a.encoding : "halfdiff",
             *output = a.output ? a.output : "log1p";
  char *data_list = a.data.copy;
  int n_data = a.data.n;
  double steps = a.steps, minutes = a.minutes, rows = a.rows, lrw = a.lrw, lrl = a.lrl, l2 = a.l2,
         decay = a.decay, gamma = a.gamma, seed = a.seed, ckpt = a.ckpt, nval = a.nval,
         width = a.width, blocks = a.blocks, octaves = a.octaves, bweight = a.bweight,
         stop_at = a.stop_at, energy = a.energy, energy_brdfs = a.energy_brdfs;
  cli_progress_state prog = a.prog;
  if (n_data == 0 || !s.run_dir || !*s.run_dir) {
    free(data_list);
    return cli_usage_error("train", "--data and --run are required");
  }
  if (a.init_bundle && arch_given) {
    free(data_list);
    return cli_usage_error("train", "--init-bundle takes the bundle's decoder architecture: "
                                    "give no --preset, --width, --blocks, --encoding, --octaves "
                                    "or --output with it");
  }
  nbrdf_error err = {0};
  nbrdf_status st;
  nbrdf_model *init = NULL;
  if (a.init_bundle && nbrdf_model_load(a.init_bundle, &init, &err)) {
    free(data_list);
    return cli_fail_error("train", &err);
  }
  s.init = init;
  if (width > 0 || blocks > 0) {
    model_encoding enc = {MODEL_ENCODING_HALFDIFF, (int)octaves};
    if (!model_encoding_kind_parse(encoding, &enc.kind))
      return cli_usage_error("train", "unknown encoding '%s' (cartesian, halfdiff)", encoding);
    model_output out = !strcmp(output, "f") ? MODEL_OUTPUT_F : MODEL_OUTPUT_LOG1P;
    if (strcmp(output, "f") && strcmp(output, "log1p"))
      return cli_usage_error("train", "unknown output '%s' (f, log1p)", output);
    st = model_decoder_config_make(32, enc, out, width > 0 ? (int)width : 64,
                                   blocks > 0 ? (int)blocks : 3, 1, &s.arch, &err);
  } else {
    st = model_decoder_preset(preset, 32, &s.arch, &err);
  }
  if (st) {
    free(data_list);
    nbrdf_model_destroy(init);
    return cli_fail_error("train", &err);
  }
  cli_inputs inputs; /* the run's checkpoint is read and rewritten: resuming is the point */
  cli_inputs_init(&inputs);
  cli_inputs_add_model(&inputs, init);
  for (int k = 0; k < n_data; k++)
    cli_inputs_add(&inputs, data[k]);
  static const char *const run_files[] = {"checkpoint.safetensors", "decoder.safetensors",
                                          "log.csv", NULL};
  if (cli_outputs_check_in("train", &inputs, s.run_dir, run_files) != CLI_EXIT_OK) {
    free(data_list);
    nbrdf_model_destroy(init);
    return CLI_EXIT_FAILURE;
  }
  s.data = data, s.n_data = n_data;
  s.steps = (int64_t)steps, s.max_seconds = 60.0 * minutes, s.rows_per_brdf = (int)rows;
  s.lr_weights = (float)lrw, s.lr_latent = (float)lrl, s.latent_l2 = (float)l2;
  s.decay_every = (int)decay, s.decay_gamma = (float)gamma, s.seed = (uint64_t)seed;
  s.checkpoint_seconds = 60.0 * ckpt, s.validation_brdfs = (int)nval, s.brdf_weight = bweight;
  s.stop_at_step = (int64_t)stop_at;
  s.energy.lambda = (float)energy, s.energy_brdfs = (int)energy_brdfs;
  s.energy.floor_margin = (float)a.energy_floor;
  cli_progress_start(&prog);
  s.progress = cli_progress, s.user = &prog, s.cancel = cli_cancel_flag();
  cli_cancel_watch();
  train_decoder_result r;
  st = train_decoder_run(&s, &r, &err);
  cli_cancel_unwatch();
  nbrdf_model_destroy(init);
  if (!prog.json) fputc('\n', stderr);
  cli_train_limits_note("checkpoint.safetensors", r.legacy_resume);
  free(data_list);
  if (st == NBRDF_ERR_CANCELLED) {
    fprintf(stderr, "train: %s\n", err.message);
    return CLI_EXIT_FAILURE;
  }
  if (st) return cli_fail_error("train", &err);
  printf("train decoder: %lld steps (resumed from %lld), train loss %.5g, validation loss %.5g\n",
         (long long)r.steps_done, (long long)r.resumed_from, r.train_loss, r.val_loss);
  return CLI_EXIT_OK;
}

int cmd_train(int argc, char **argv) {
  if (argc < 2 || cli_is_help(argv[1])) {
    cmd_train_usage(argc < 2 ? stderr : stdout);
    return argc < 2 ? CLI_EXIT_USAGE : CLI_EXIT_OK;
  }
  if (!strcmp(argv[1], "decoder")) return train_decoder(argc, argv);
  if (!strcmp(argv[1], "tables")) return cmd_train_tables(argc, argv);
  if (!strcmp(argv[1], "layering")) return cmd_train_layering(argc, argv);
  if (!strcmp(argv[1], "bundle")) return cmd_train_bundle(argc, argv);
  if (!strcmp(argv[1], "sampler")) return cmd_train_sampler(argc, argv);
  return cli_usage_error(
      "train", "unknown training '%s' (decoder, tables, layering, sampler, bundle)", argv[1]);
}
