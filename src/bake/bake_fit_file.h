/* A fit kept for later bakes (nbrdf/fit.h): the object behind nbrdf_fit and
 * its file, the .nbfit (docs/FIT-FILE.md): one safetensors file holding the
 * fit result (bake_accuracy.h) whole, with the decoders the fit made stored
 * as their own safetensors files' tensors and metadata under a prefix, so
 * that they load through the decoder's own reader and serialise back to the
 * same bytes (the textures' nbrdf:decoderChecksum). */
#ifndef NBRDF_BAKE_BAKE_FIT_FILE_H
#define NBRDF_BAKE_BAKE_FIT_FILE_H

#include <stdint.h>

#include "bake/bake_accuracy.h"
#include "nbrdf/fit.h"

#define BAKE_FIT_FORMAT "nbrdf-fit"
#define BAKE_FIT_VERSION "1"

struct nbrdf_fit {
  bake_fit_result r;
  /* The options that shape the tuples, and the fit's level. */
  nbrdf_bake_accuracy accuracy;
  nbrdf_roughness roughness;
  nbrdf_range_policy range;
  nbrdf_resample resample;
  int quantise_bits;
  int tiles;
  char model_checksum[17];
  char base_decoder[17];     /* the model's own decoder the fit started from; "": the bundle's */
  char decoder_checksum[17]; /* of the decoder the textures carry; "": none (fitted) */
  char file_checksum[17];    /* of the file it was read from or written to */
  /* Per parameter: the inputs the fit was made from, one entry per distinct
   * input ("map fnv1a64=HEX read=..." or "constant V[,V,V]"), joined by "\n". */
  char *inputs[NBRDF_BAKE_PARAM_COUNT];
  char *path; /* the file, for messages */
};

/* The decoder checksum the textures of `f->r` carry (16 hex digits into hex[17]; "" for
 * a fit without a decoder of its own). */
nbrdf_status bake_fit_decoder_checksum(const bake_fit_result *r, char hex[17], nbrdf_error *err);

/* Writes `f` to `path` (a temporary file renamed; never one of the n_inputs `inputs`);
 * f->file_checksum receives the written file's checksum. */
nbrdf_status bake_fit_file_write(nbrdf_fit *f, const char *path, const char *const *inputs,
                                 int n_inputs, nbrdf_error *err);

/* Reads `path` into `f` (zeroed first; on failure freed again). */
nbrdf_status bake_fit_file_read(const char *path, nbrdf_fit *f, nbrdf_error *err);

/* Frees what `f` owns (not f itself). */
void bake_fit_release(nbrdf_fit *f);

#endif
