/* The model bundle on disk (include/nbrdf/model.h has the layout) and the
 * internal layout of the public nbrdf_model handle.
 *
 * model.json:
 *   {"format": "nbrdf-model", "version": 1, "name": "...", "trained": false,
 *    "latent_dim": 32, "seed": 1, "checksum": "<16 hex>",
 *    "decoder": {"preset", "encoding", "octaves", "output", "macs", "params"},
 *    "layering": {"preset", "macs", "params", "sigma_t_input": "log1p"},
 *    "sampler": {"preset", "macs", "params", "sigma_min"},
 *    "base_tables": {"dielectric": {"alpha1": [..], "eta": [..]},
 *                    "conductor": {"alpha2": [..], "r0": [..]}},
 *    "note": "...",
 *    "reads_textures_of": [{"name": "...", "checksum": "<16 hex>"}, ...]}   (optional)
 * Load reads name, trained and latent_dim from it (latent_dim must agree with
 * every file); the safetensors files are the truth, and every other value it
 * states about the networks and tables must equal theirs (bundle_check.c).
 * The checksum is required, and one that differs from the files' is refused
 * (a file was damaged or replaced without rewriting model.json).
 * "reads_textures_of" names earlier bundles whose decoder is byte for byte this one's
 * (`nbrdf train bundle --reads-textures-of DIR` checks that when it writes the list), so
 * textures baked with them decode here: a retrained layering network or tables need not
 * orphan the textures users already have. */
#ifndef NBRDF_MODEL_BUNDLE_H
#define NBRDF_MODEL_BUNDLE_H

#include <stdint.h>
#include <stdio.h>

#include "model/bundle_parts.h"
#include "nbrdf/model.h"

/* A derived model of `base` (or of base's parent): with `bytes` (size
 * bytes of a decoder.safetensors, copied, at most NBRDF_DECODER_BYTES_MAX)
 * as its own decoder, or a plain new reference to the bundle's parts when
 * bytes is NULL. `label` starts messages. */
nbrdf_status model_derive(const nbrdf_model *base, const void *bytes, size_t size,
                          const char *label, nbrdf_model **out, nbrdf_error *err);

/* `base` with a decoder built in memory (a fine-tuned copy, say): `dec` is
 * serialised to safetensors bytes, which the returned model decodes with and
 * a bake embeds (so the texture holds exactly what was used). `dec` stays
 * the caller's. */
nbrdf_status model_with_decoder_net(const nbrdf_model *base, const model_decoder *dec,
                                    nbrdf_model **out, nbrdf_error *err);


/* Writes a bundle into `dir` (created if missing): each file atomically; the
 * checksum of the result in *checksum (may be NULL). Dimensions are checked
 * before anything is written. */
nbrdf_status model_bundle_save(const char *dir, const model_bundle_parts *parts, uint64_t *checksum,
                               nbrdf_error *err);

/* base_tables.safetensors alone (training writes it before a bundle exists). */
nbrdf_status model_tables_save(const model_base_table *const tables[2], const char *path,
                               nbrdf_error *err);

/* `nbrdf bundle init`: random networks (decoder preset `decoder_preset`,
 * layering "paper", sampler "default") and base tables of smooth random
 * latents over the paper's parameter ranges, marked untrained. */
nbrdf_status model_bundle_init_random(const char *dir, const char *name, uint64_t seed,
                                      const char *decoder_preset, nbrdf_error *err);

/* Prints name, training state, checksum, architecture, MACs per query and
 * table grids (`nbrdf bundle info`). */
void model_bundle_describe(const nbrdf_model *model, FILE *out);

#endif
