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
      "                          [--energy-brdfs K (8 pairs per batch)]] (decoded loss)\n"
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
      "checkpoints and stops.\n"
      "\n"
      "architecture (a preset, or your own residual MLP):\n"
      "  --preset NAME       paper, large, medium (default), small\n"
      "  --width W --blocks B [--encoding cartesian|halfdiff] [--octaves K]\n"
      "                      [--output f|log1p]\n"
      "training:\n"
      "  --steps N           total steps (20000); each step draws --rows-per-brdf samples\n"
      "                      of every BRDF (16)\n"
      "  --minutes M         stop (checkpointed) after M minutes of this invocation\n"
      "  --stop-at-step N    stop (checkpointed) after N steps of the whole run\n"
      "  --lr-weights X (2e-3)  --lr-latent X (1e-2)  --latent-l2 X (1e-4)\n"
      "  --decay-every N (5000) --decay-gamma X (0.5)  --loss l1-log1p|l1\n"
      "  --brdf-weight P (0)  weigh BRDF b's loss by max(mean log(1+f), 0.01)^-P\n"
      "  --seed S (1)  --checkpoint-minutes M (5)  --validation N (24 held-out BRDFs)\n"
      "  --energy LAMBDA (0: off)  penalise decoded directional albedo above the ground\n"
      "                      truth's (+ 2 standard errors + 0.01, at most 1) with weight LAMBDA\n"
      "  --energy-angles LIST (0,40,60,75,85,89 degrees)  --energy-brdfs K (32 per step)\n"
      "  --progress=json     progress as JSON lines on stdout (text on stderr without it)\n"
      "A checkpoint records the settings a resume must share (nbrdf.options): another\n"
      "value is refused, naming the setting and both values.\n"
      "\n"
      "trainer flags (tables, layering, sampler: one trainer runs every fit; a step is\n"
      "a projection step, a batch of pairs, a batch of latents):\n" CLI_TRAIN_LIMITS_HELP "\n"
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
      "bundle's decoder, so a retrained layering network or tables keep old textures).\n");
}

typedef struct num_option {
  const char *name;
  double lo, hi;
  double *value;
} num_option;

static int train_decoder(int argc, char **argv) {
  train_decoder_settings s;
  train_decoder_settings_default(&s);
  const char *data[64], *preset = "medium", *encoding = "halfdiff", *output = "log1p";
  char *data_list = NULL;
  int n_data = 0;
  double steps = (double)s.steps, minutes = 0, rows = s.rows_per_brdf, lrw = s.lr_weights,
         lrl = s.lr_latent, l2 = s.latent_l2, decay = s.decay_every, gamma = s.decay_gamma,
         seed = (double)s.seed, ckpt = s.checkpoint_seconds / 60.0, nval = s.validation_brdfs,
         width = 0, blocks = 0, octaves = 0, bweight = s.brdf_weight, stop_at = 0,
         energy = s.energy.lambda, energy_brdfs = s.energy_brdfs;
  num_option nums[] = {
      {"--steps", 1, 1e12, &steps},
      {"--minutes", 0, 1e9, &minutes},
      {"--stop-at-step", 0, 1e12, &stop_at},
      {"--rows-per-brdf", 1, 65536, &rows},
      {"--lr-weights", 0, 1, &lrw},
      {"--lr-latent", 0, 10, &lrl},
      {"--latent-l2", 0, 1e3, &l2},
      {"--decay-every", 0, 1e9, &decay},
      {"--decay-gamma", 1e-6, 1, &gamma},
      {"--seed", 0, 9007199254740992.0, &seed},
      {"--checkpoint-minutes", 1e-3, 1e6, &ckpt},
      {"--validation", 0, 4096, &nval},
      {"--width", 1, 4096, &width},
      {"--blocks", 1, 64, &blocks},
      {"--octaves", 0, MODEL_ENCODING_MAX_OCTAVES, &octaves},
      {"--brdf-weight", 0, 2, &bweight},
      {"--energy", 0, 1e6, &energy},
      {"--energy-brdfs", 1, 4096, &energy_brdfs},
  };
  cli_progress_state prog = cli_progress_init(CLI_PROGRESS_COUNT, NULL);
  for (int i = 2; i < argc; i++) {
    const char *v;
    int matched = 0;
    for (size_t k = 0; k < sizeof nums / sizeof nums[0] && !matched; k++)
      if ((v = cli_option_value(argc, argv, &i, nums[k].name))) {
        if (!cli_parse_double(v, nums[k].value) || *nums[k].value < nums[k].lo ||
            *nums[k].value > nums[k].hi)
          return cli_usage_error("train", "%s '%s' is not a number in [%g, %g]", nums[k].name, v,
                                 nums[k].lo, nums[k].hi);
        matched = 1;
      }
    if (matched) continue;
    if ((v = cli_option_value(argc, argv, &i, "--data"))) {
      free(data_list);
      data_list = strdup(v);
      n_data = data_list ? cli_train_split_list(data_list, data, 64) : 0;
    } else if ((v = cli_option_value(argc, argv, &i, "--run"))) {
      s.run_dir = v;
    } else if ((v = cli_option_value(argc, argv, &i, "--preset"))) {
      preset = v;
    } else if ((v = cli_option_value(argc, argv, &i, "--energy-angles"))) {
      nbrdf_error e2 = {0};
      if (model_energy_parse_angles(v, "--energy-angles", &s.energy, &e2)) {
        free(data_list);
        return cli_usage_error("train", "%s", e2.message);
      }
    } else if ((v = cli_option_value(argc, argv, &i, "--encoding"))) {
      encoding = v;
    } else if ((v = cli_option_value(argc, argv, &i, "--output"))) {
      output = v;
    } else if ((v = cli_option_value(argc, argv, &i, "--loss"))) {
      if (!model_loss_parse(v, &s.loss))
        return cli_usage_error("train", "unknown loss '%s' (l1-log1p, l1)", v);
    } else if (cli_progress_flag(argv[i], &prog)) {
    } else if (cli_is_help(argv[i])) {
      cmd_train_usage(stdout);
      free(data_list);
      return CLI_EXIT_OK;
    } else {
      free(data_list);
      return cli_usage_error("train", "unexpected argument '%s'", argv[i]);
    }
  }
  if (n_data == 0 || !s.run_dir || !*s.run_dir) {
    free(data_list);
    return cli_usage_error("train", "--data and --run are required");
  }
  nbrdf_error err = {0};
  nbrdf_status st;
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
    return cli_fail_error("train", &err);
  }
  cli_inputs inputs; /* the run's checkpoint is read and rewritten: resuming is the point */
  cli_inputs_init(&inputs);
  for (int k = 0; k < n_data; k++)
    cli_inputs_add(&inputs, data[k]);
  static const char *const run_files[] = {"checkpoint.safetensors", "decoder.safetensors",
                                          "log.csv", NULL};
  if (cli_outputs_check_in("train", &inputs, s.run_dir, run_files) != CLI_EXIT_OK) {
    free(data_list);
    return CLI_EXIT_FAILURE;
  }
  s.data = data, s.n_data = n_data;
  s.steps = (int64_t)steps, s.max_seconds = 60.0 * minutes, s.rows_per_brdf = (int)rows;
  s.lr_weights = (float)lrw, s.lr_latent = (float)lrl, s.latent_l2 = (float)l2;
  s.decay_every = (int)decay, s.decay_gamma = (float)gamma, s.seed = (uint64_t)seed;
  s.checkpoint_seconds = 60.0 * ckpt, s.validation_brdfs = (int)nval, s.brdf_weight = bweight;
  s.stop_at_step = (int64_t)stop_at;
  s.energy.lambda = (float)energy, s.energy_brdfs = (int)energy_brdfs;
  cli_progress_start(&prog);
  s.progress = cli_progress, s.user = &prog, s.cancel = cli_cancel_flag();
  cli_cancel_watch();
  train_decoder_result r;
  st = train_decoder_run(&s, &r, &err);
  cli_cancel_unwatch();
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
