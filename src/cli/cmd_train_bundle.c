/* nbrdf train bundle: trained parts (decoder, tables, layering, sampler, card) into a
 * model bundle. */
#include <stdio.h>
#include <stdlib.h>

#include "cli/cli.h"
#include "cli/cli_outputs.h"
#include "cli/cmd_train.h"
#include "model/bundle.h"
#include "model/files.h"

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
