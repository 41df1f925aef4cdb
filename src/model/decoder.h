/* The decoder (evaluation network, paper §3.2): one row per (query, colour
 * channel) holds [latent (latent_dim) | encoding(ωi, ωo)] and gives one value,
 * the single-channel BRDF f(ωi, ωo) without cosine. Each colour channel is its
 * own row with its own latent; the directions are shared.
 *
 * Output transforms (the network's raw output o → f):
 * - MODEL_OUTPUT_F:     f = max(o, 0) (the paper);
 * - MODEL_OUTPUT_LOG1P: o predicts g = log(1 + f), f = exp(min(max(o, 0), 80)) − 1
 *   (clamped so that f is >= 0 and finite). Specular peaks span orders of
 *   magnitude; in log space they cost the network no more than the tails.
 *
 * Presets (MACs = GEMM multiply-adds per query, nn_spec_macs):
 *   paper   cartesian, f,     width 256, 8 residual + 8 plain blocks   1,058,560
 *   large   halfdiff,  log1p, width 128, 3 residual + 3 plain blocks     103,296
 *   medium  halfdiff,  log1p, width 64,  3 residual + 3 plain blocks      27,072
 *   small   halfdiff,  log1p, width 32,  2 residual + 2 plain blocks       5,344
 * ("paper" is the released configuration: 32 + 6 = 38 inputs, plain 256 → 1 output.)
 *
 * File metadata (besides netio.h's): nbrdf.encoding ("cartesian" | "halfdiff"),
 * nbrdf.octaves, nbrdf.output ("f" | "log1p"), nbrdf.preset (informative). */
#ifndef NBRDF_MODEL_DECODER_H
#define NBRDF_MODEL_DECODER_H

#include <stddef.h>
#include <stdint.h>

#include "model/encoding.h"
#include "model/netio.h"

typedef enum model_output { MODEL_OUTPUT_F = 0, MODEL_OUTPUT_LOG1P = 1 } model_output;

typedef struct model_decoder_config {
  char preset[32]; /* informative; "custom" when not a preset */
  int latent_dim;  /* 32 in the paper */
  model_encoding encoding;
  model_output output;
  nn_spec spec; /* inputs = latent_dim + encoding width, 1 output */
} model_decoder_config;

typedef struct model_decoder {
  model_decoder_config cfg;
  nn_network *nn;
} model_decoder;

/* Names of the presets, NULL-terminated. */
extern const char *const model_decoder_presets[];

/* A preset's configuration for the given latent dimension. */
nbrdf_status model_decoder_preset(const char *name, int latent_dim, model_decoder_config *cfg,
                                  nbrdf_error *err);
/* A residual MLP (nn_spec_resmlp) configuration of your own. */
nbrdf_status model_decoder_config_make(int latent_dim, model_encoding encoding, model_output output,
                                       int width, int blocks, int interleave_plain,
                                       model_decoder_config *cfg, nbrdf_error *err);

/* The compact decoder of `nbrdf bake --compact K[,WIDTH]`: halfdiff, log1p output,
 * PLAIN(width), one residual block, linear output: (K + 6) w + w^2 + w multiply-adds.
 * Here rather than in bake/ so that tools which only evaluate it (bench_shader on a GPU
 * machine) link the model layer alone. */
#define MODEL_COMPACT_MAX_DIM 8
nbrdf_status model_decoder_compact_config(int dim, int width, model_decoder_config *cfg,
                                          nbrdf_error *err);

/* Builds the network, initialised deterministically from `seed`. */
nbrdf_status model_decoder_create(const model_decoder_config *cfg, uint64_t seed,
                                  model_decoder **out, nbrdf_error *err);
void model_decoder_destroy(model_decoder *dec);

int model_decoder_inputs(const model_decoder *dec);
int64_t model_decoder_macs(const model_decoder *dec);
const char *model_output_name(model_output output);

/* Fills decoder input rows for n queries × channels: row (k·channels + c) is
 * [latents[(k·channels + c) · D ..] | encoding(wi[k], wo[k])]. */
void model_decoder_fill_inputs(const model_decoder *dec, size_t n, int channels,
                               const float *latents, const float *wi, const float *wo, float *x);

/* f from the raw network output (the transform above). */
float model_output_to_f(model_output output, float o);

/* f[k·channels + c] for n queries; `runner` (INFER or TRAIN mode) of this
 * decoder; any n (chunked by the runner's batch). */
nbrdf_status model_decoder_eval(const model_decoder *dec, model_runner *runner, size_t n,
                                int channels, const float *latents, const float *wi,
                                const float *wo, float *f, nbrdf_error *err);

/* Save and load (netio.h plus the keys above). Load checks that the spec's
 * inputs equal latent_dim + encoding width and that it has 1 output. */
nbrdf_status model_decoder_save(const model_decoder *dec, const char *path, uint64_t *checksum,
                                nbrdf_error *err);
/* The bytes model_decoder_save would write, in a malloc'ed buffer. */
nbrdf_status model_decoder_serialize(const model_decoder *dec, void **bytes, size_t *size,
                                     nbrdf_error *err);
nbrdf_status model_decoder_read(const nn_st_reader *reader, model_decoder **out, nbrdf_error *err);
nbrdf_status model_decoder_load(const char *path, model_decoder **out, nbrdf_error *err);

#endif
