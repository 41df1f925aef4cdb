#include "cli/cli.h"

/* One line per subcommand; each is defined in cmd_<name>.c. */
#define DECLARE(name)                                                                              \
  int cmd_##name(int argc, char **argv);                                                           \
  void cmd_##name##_usage(FILE *out);                                                              \
  void cmd_##name##_options(cli_opt_visit visit, void *user);
DECLARE(help)
DECLARE(bundle)
DECLARE(eval)
DECLARE(bake)
DECLARE(fit)
DECLARE(info)
DECLARE(verify)
DECLARE(render)
DECLARE(dataset)
DECLARE(train)
DECLARE(evaluate)
DECLARE(completion)
DECLARE(farm)

const cli_command cli_commands[] = {
    {"help", "show help for nbrdf or one of its commands", cmd_help, cmd_help_usage,
     cmd_help_options},
    {"bundle", "create an untrained model bundle, or describe one", cmd_bundle, cmd_bundle_usage,
     cmd_bundle_options},
    {"eval", "ground-truth BRDF values at point queries (CSV in, CSV out)", cmd_eval,
     cmd_eval_usage, cmd_eval_options},
    {"bake", "bake parameter maps into a latent OpenEXR texture", cmd_bake, cmd_bake_usage,
     cmd_bake_options},
    {"fit", "fit an accuracy level once, for bakes of many textures (nbrdf bake --fit)", cmd_fit,
     cmd_fit_usage, cmd_fit_options},
    {"info", "describe a latent texture", cmd_info, cmd_info_usage, cmd_info_options},
    {"verify", "check a latent texture against the ground truth of its parameters", cmd_verify,
     cmd_verify_usage, cmd_verify_options},
    {"render", "render a latent texture on a sphere or plane (neural or reference)", cmd_render,
     cmd_render_usage, cmd_render_options},
    {"dataset", "generate, resume or check ground-truth training data", cmd_dataset,
     cmd_dataset_usage, cmd_dataset_options},
    {"train", "train the networks (checkpointed, resumable)", cmd_train, cmd_train_usage,
     cmd_train_options},
    {"evaluate", "model quality on the held-out sets (docs/METRICS.md)", cmd_evaluate,
     cmd_evaluate_usage, cmd_evaluate_options},
    {"farm", "plan (and submit) a tile set's bake on a Slurm cluster", cmd_farm, cmd_farm_usage,
     cmd_farm_options},
    {"completion", "print the shell completion script (bash or zsh)", cmd_completion,
     cmd_completion_usage, cmd_completion_options},
};
const int cli_command_count = (int)(sizeof cli_commands / sizeof cli_commands[0]);
