/* nbrdf train bundle: trained parts (decoder, tables, layering, sampler, card) into a
 * model bundle. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_outputs.h"
#include "cli/cmd_train.h"
#include "core/error.h"
#include "model/bundle.h"
#include "model/files.h"

/* The reads list of a bundle that takes over `dir`'s textures: dir itself and every bundle
 * dir reads, provided dir's decoder.safetensors has exactly the bytes of `decoder`. */
static nbrdf_status reads_of(const char *dir, const char *decoder, model_bundle_ref *reads,
                             int *n_reads, nbrdf_error *err) {
  nbrdf_model *old = NULL;
  char *a = NULL, *b = NULL, path[4200];
  size_t na = 0, nb = 0;
  nbrdf_status st = nbrdf_model_load(dir, &old, err);
  snprintf(path, sizeof path, "%s/decoder.safetensors", dir);
  if (!st) st = model_read_file(decoder, NBRDF_DECODER_BYTES_MAX, &a, &na, err);
  if (!st) st = model_read_file(path, NBRDF_DECODER_BYTES_MAX, &b, &nb, err);
  if (!st && (na != nb || memcmp(a, b, na) != 0))
    st = core_fail(err, NBRDF_ERR_MISMATCH,
                   "--reads-textures-of %s: its decoder (%s) is not byte for byte %s; textures "
                   "decode with their bundle's decoder, so only a bundle with the same one can "
                   "read them",
                   dir, path, decoder);
  if (!st && old->n_reads + 1 > MODEL_READS_MAX)
    st = core_fail(err, NBRDF_ERR_ARGUMENT, "--reads-textures-of %s: more than %d bundles", dir,
                   MODEL_READS_MAX);
  if (!st) {
    snprintf(reads[0].name, sizeof reads[0].name, "%s", old->name);
    snprintf(reads[0].checksum_hex, sizeof reads[0].checksum_hex, "%s", old->checksum_hex);
    memcpy(reads + 1, old->reads, (size_t)old->n_reads * sizeof *reads);
    *n_reads = 1 + old->n_reads;
  }
  free(a);
  free(b);
  nbrdf_model_destroy(old);
  return st;
}

typedef struct bundle_args {
  const char *out, *name, *decoder, *tables, *layering, *sampler, *card, *note, *reads_dir;
} bundle_args;

static void bundle_options(void *args, cli_opt_visit visit, void *user) {
  bundle_args *a = args;
  // clang-format off
  const cli_opt t[] = {
      {.type = CLI_OPT_PATH, .name = "--output", .alias = "-o", .meta = "DIR", .dest = &a->out,
       .help = "the bundle folder to write"},
      {.type = CLI_OPT_PATH, .name = "--decoder", .meta = "F", .dest = &a->decoder,
       .help = "decoder.safetensors"},
      {.type = CLI_OPT_PATH, .name = "--tables", .meta = "F", .dest = &a->tables,
       .help = "base_tables.safetensors"},
      {.type = CLI_OPT_PATH, .name = "--layering", .meta = "F", .dest = &a->layering,
       .help = "layering.safetensors"},
      {.type = CLI_OPT_PATH, .name = "--sampler", .meta = "F", .dest = &a->sampler,
       .help = "sampler.safetensors (default: initial weights)"},
      {.type = CLI_OPT_STRING, .name = "--name", .meta = "NAME", .dest = &a->name,
       .help = "the model's name (default)"},
      {.type = CLI_OPT_PATH, .name = "--card", .meta = "MODEL_CARD.md", .dest = &a->card,
       .help = "the model card"},
      {.type = CLI_OPT_STRING, .name = "--note", .meta = "TEXT", .dest = &a->note,
       .help = "one line for model.json"},
      {.type = CLI_OPT_PATH, .name = "--reads-textures-of", .meta = "OLD_DIR",
       .dest = &a->reads_dir,
       .help = "the new bundle also reads textures baked with OLD_DIR\n"
               "(same decoder bytes only)"},
      {0},
  };
  // clang-format on
  visit(user, "bundle", t);
}

void cmd_train_bundle_options(cli_opt_visit visit, void *user) {
  bundle_args a = {NULL, "default", NULL, NULL, NULL, NULL, NULL, NULL, NULL};
  bundle_options(&a, visit, user);
}

int cmd_train_bundle(int argc, char **argv) {
  bundle_args a = {NULL, "default", NULL, NULL, NULL, NULL, NULL, NULL, NULL};
  int rc = cli_train_parse("bundle", argc, argv, bundle_options, &a);
  if (rc) return rc == CLI_OPTIONS_HELP ? CLI_EXIT_OK : rc;
  const char *out = a.out, *name = a.name, *decoder = a.decoder, *tables = a.tables,
             *layering = a.layering, *sampler = a.sampler, *card = a.card, *note = a.note,
             *reads_dir = a.reads_dir;
  if (!out || !decoder || !tables || !layering)
    return cli_usage_error("train", "bundle: -o, --decoder, --tables and --layering are required");
  cli_inputs inputs;
  cli_inputs_init(&inputs);
  const char *read[5] = {decoder, tables, layering, sampler, card};
  for (int k = 0; k < 5; k++)
    cli_inputs_add(&inputs, read[k]);
  /* The old bundle is read too: writing the new one over it would leave no bundle that
   * the list could name truthfully. */
  cli_inputs_add_bundle_dir(&inputs, reads_dir);
  int refused = cli_outputs_check_bundle("train", &inputs, out) != CLI_EXIT_OK;
  cli_inputs_free(&inputs);
  if (refused) return CLI_EXIT_FAILURE;
  nbrdf_error err = {0};
  model_decoder *dec = NULL;
  model_layering *lay = NULL;
  model_sampler *smp = NULL;
  model_base_table t[2];
  memset(t, 0, sizeof t); /* freed on every path, also when loading stopped before them */
  char *card_text = NULL;
  model_bundle_ref reads[MODEL_READS_MAX];
  int n_reads = 0;
  nbrdf_status st = reads_dir ? reads_of(reads_dir, decoder, reads, &n_reads, &err) : NBRDF_OK;
  if (!st) st = model_decoder_load(decoder, &dec, &err);
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
                                .tables = {&t[0], &t[1]},
                                .reads = reads,
                                .n_reads = n_reads};
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
