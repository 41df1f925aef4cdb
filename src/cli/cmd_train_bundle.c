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

int cmd_train_bundle(int argc, char **argv) {
  const char *out = NULL, *name = "default", *decoder = NULL, *tables = NULL, *layering = NULL,
             *sampler = NULL, *card = NULL, *note = NULL, *reads_dir = NULL;
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
    else if ((v = cli_option_value(argc, argv, &i, "--reads-textures-of")))
      reads_dir = v;
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
