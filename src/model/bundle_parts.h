/* A model bundle's parts in memory (struct nbrdf_model) and as saved
 * (model_bundle_parts): what the bundle's loader (bundle.c) and its
 * model.json reader and writer (bundle_json.c) share. */
#ifndef NBRDF_MODEL_BUNDLE_PARTS_H
#define NBRDF_MODEL_BUNDLE_PARTS_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "model/base_table.h"
#include "model/decoder.h"
#include "model/layering.h"
#include "model/sampler.h"
#include "nbrdf/model.h"

#define MODEL_BUNDLE_FORMAT "nbrdf-model"
#define MODEL_BUNDLE_VERSION 1

/* An earlier bundle whose textures this one reads (its decoder is this one's). */
#define MODEL_READS_MAX 8
typedef struct model_bundle_ref {
  char name[64];
  char checksum_hex[17];
} model_bundle_ref;

/* The energy audit's slopes (audit_slopes.h): per region of MODEL_AUDIT_REGIONS x
 * MODEL_AUDIT_REGIONS bins of normalised (alpha1, alpha2), one per parameter and
 * direction (up: the tuple's parameter above the measured one's; down: below). */
#define MODEL_AUDIT_REGIONS 8
#define MODEL_AUDIT_PARAMS 6
#define MODEL_AUDIT_DIRS 2

/* The four weight files, in checksum order. */
extern const char *const model_bundle_files[4];
/* model.json, the four model_bundle_files and MODEL_CARD.md (nbrdf_model_files). */
enum { MODEL_FILES = 6 };

struct nbrdf_model {
  char name[64];
  int trained;
  int latent_dim;
  uint64_t checksum;
  char checksum_hex[17];
  model_decoder *decoder;
  model_layering *layering;
  model_sampler *sampler;
  model_base_table tables[2]; /* indexed by nbrdf_base_kind */
  const char *files[MODEL_FILES]; /* nbrdf_model_files: model.json, model_bundle_files, card */
  char *files_text;           /* owns the strings of files[] */
  /* A derived model (model_derive.c) shares everything above but its
   * decoder with `parent`, a loaded bundle it holds a reference to; it owns
   * `decoder` only when own_decoder is set. */
  nbrdf_model *parent;
  atomic_int extra_refs; /* derived models holding this one (0 when none) */
  int own_decoder;
  unsigned char *decoder_bytes; /* own decoder: its safetensors bytes (a bake embeds them) */
  size_t decoder_size;
  char decoder_checksum_hex[17]; /* FNV-1a 64 of decoder_bytes */
  model_bundle_ref reads[MODEL_READS_MAX]; /* model.json's "reads_textures_of" */
  int n_reads;
  /* model.json's "audit_slopes", measured for these weights (a derived model
   * carries its bundle's); has_audit_slopes 0: none. */
  double audit_slope[MODEL_AUDIT_REGIONS][MODEL_AUDIT_REGIONS][MODEL_AUDIT_PARAMS][MODEL_AUDIT_DIRS];
  int has_audit_slopes;
  int audit_slopes_both_ways; /* read from the first form: one slope a parameter, both ways */
};

/* What a bundle is made of, for saving (all borrowed). */
typedef struct model_bundle_parts {
  const char *name;
  int trained;
  uint64_t seed;    /* recorded in model.json (0 = not applicable) */
  const char *note; /* one line for model.json, may be NULL */
  const char *card; /* MODEL_CARD.md text; NULL = a generated summary */
  const model_decoder *decoder;
  const model_layering *layering;
  const model_sampler *sampler;
  const model_base_table *tables[2];
  const model_bundle_ref *reads; /* "reads_textures_of"; n_reads may be 0 */
  int n_reads;
} model_bundle_parts;

#endif
