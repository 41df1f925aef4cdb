/* One fit per material: the plan/fit stage of the fitted, specialised and
 * compact accuracy levels (nbrdf/bake.h) made once over every tile of a set
 * and kept in a .nbfit file (docs/FIT-FILE.md), then baked from, tile by
 * tile and on any machine, with no fitting (nbrdf_bake_options.fit). Every
 * tile baked with one fit carries the same decoder and the same correction.
 *
 * Example (`model` a loaded bundle, `in` the inputs of one tile; a set passes an array):
 *   nbrdf_error err;
 *   nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
 *   o.accuracy = NBRDF_BAKE_SPECIALISED;
 *   nbrdf_fit *fit = NULL;
 *   if (nbrdf_fit_run(model, &in, 1, &o, "scene.nbfit", NULL, &err) == NBRDF_OK &&
 *       nbrdf_fit_open("scene.nbfit", &fit, &err) == NBRDF_OK) {
 *     o.fit = fit;
 *     if (nbrdf_bake(model, &in, &o, "latent.1001.exr", NULL, &err) != NBRDF_OK)
 *       fprintf(stderr, "bake: %s\n", err.message);
 *   }
 *   nbrdf_fit_destroy(fit);
 *
 * A fit is immutable once opened: several bakes (threads) may share one. */
#ifndef NBRDF_FIT_H
#define NBRDF_FIT_H

#include <stddef.h>
#include <stdint.h>

#include "nbrdf/bake.h"
#include "nbrdf/model.h"
#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct nbrdf_fit nbrdf_fit;

/* What a fit is (nbrdf_fit_run's report, nbrdf_fit_describe). */
typedef struct nbrdf_fit_info {
  nbrdf_bake_accuracy accuracy;
  int tiles;             /* the sets of inputs (tiles) it was fitted over */
  size_t distinct;       /* distinct tuples across them */
  size_t fitted_tuples, heldout_tuples;
  double heldout_error, heldout_error_fast; /* median lobe errors, as nbrdf_bake_report's */
  double budget;
  char model_checksum[17]; /* the bundle it was fitted with */
  /* The decoder every texture baked with it carries (specialised: the fine-tuned one;
   * compact: the distilled one; 16 hex digits, as the textures' nbrdf:decoderChecksum),
   * "" for fitted (its textures decode with the bundle's decoder). */
  char decoder_checksum[17];
  char file_checksum[17]; /* FNV-1a 64 of the .nbfit file (textures record it) */
} nbrdf_fit_info;

/* Fits level options->accuracy (fitted, specialised or compact) over the
 * n_tiles inputs `tiles` together (their distinct tuples gathered across all
 * of them; with one tile the fit nbrdf_bake makes of it, bit for bit) and
 * writes it to `path` (a temporary file renamed at the end: a failed or
 * cancelled fit leaves no file). Progress stages "gather", "ground truth",
 * "fit" (and "distil") through options->progress; options->cancel as
 * nbrdf_bake's. Each map's content hash (FNV-1a 64 of its bytes) and each
 * constant's value are recorded, so that a bake with the fit can check its
 * inputs. `info` may be NULL. */
nbrdf_status nbrdf_fit_run(const nbrdf_model *model, const nbrdf_bake_inputs *tiles,
                           size_t n_tiles, const nbrdf_bake_options *options, const char *path,
                           nbrdf_fit_info *info, nbrdf_error *err);

/* Opens a .nbfit file, checked whole (a truncated or damaged file, or
 * another format, fails with NBRDF_ERR_FORMAT naming it). */
nbrdf_status nbrdf_fit_open(const char *path, nbrdf_fit **out, nbrdf_error *err);
void nbrdf_fit_destroy(nbrdf_fit *fit); /* NULL is allowed */
void nbrdf_fit_describe(const nbrdf_fit *fit, nbrdf_fit_info *info);

/* The checks nbrdf_bake makes before it bakes with `fit`: the same bundle
 * (checksum, and the same decoder when the model has its own), the options
 * that shape the tuples (roughness, range, quantise_bits, accuracy: FAST
 * means "the fit's level"), and every input of `in` among those the fit was
 * made from (a map by its content hash and the way it is read, a constant by
 * its value; else NBRDF_ERR_MISMATCH naming the fit file, the parameter, the
 * map and what differs: a tuple the fit has not seen would be baked with a
 * correction carried from elsewhere). */
nbrdf_status nbrdf_fit_check(const nbrdf_fit *fit, const nbrdf_model *model,
                             const nbrdf_bake_inputs *in, const nbrdf_bake_options *options,
                             nbrdf_error *err);

#ifdef __cplusplus
}
#endif
#endif
