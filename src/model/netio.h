/* What the three nbrdf networks share: a runner (workspace + input/output
 * buffers sized once) and saving/loading one network to/from a safetensors
 * file whose __metadata__ carries the architecture.
 *
 * Metadata keys common to every nbrdf network file:
 *   nbrdf.format      "nbrdf-model-network"
 *   nbrdf.version     "1"
 *   nbrdf.network     "decoder" | "layering" | "sampler"
 *   nbrdf.spec        the nn architecture as JSON (nn_spec_to_json)
 *   nbrdf.latent_dim  latent floats per colour channel, e.g. "32"
 * plus each network's own keys (see decoder.h, layering.h, sampler.h). The
 * tensors are exactly the network's tensors (names of src/nn/nn.h); a file
 * with a missing, extra or misshapen tensor is refused. */
#ifndef NBRDF_MODEL_NETIO_H
#define NBRDF_MODEL_NETIO_H

#include "nn/nn.h"
#include "nn/safetensors.h"

#define MODEL_NET_FORMAT "nbrdf-model-network"
#define MODEL_NET_VERSION "1"

typedef struct model_runner {
  nn_workspace *ws;
  /* Optional (borrowed): the same network uploaded to a GPU (src/gpu); model_runner_forward
   * then runs there. NULL: the CPU (nn_forward on ws). */
  struct gpu_network *gpu;
  float *x; /* [max_batch × inputs] */
  float *y; /* [max_batch × outputs] */
  int max_batch;
} model_runner;

nbrdf_status model_runner_create(const nn_network *nn, int max_batch, nn_mode mode,
                                 model_runner *runner, nbrdf_error *err);
void model_runner_destroy(model_runner *runner); /* zeroes it; a zeroed runner is fine */
/* y = nn(x) for `rows` rows (INFER mode): on runner->gpu when set, else nn_forward. */
nbrdf_status model_runner_forward(const nn_network *nn, model_runner *runner, const float *x,
                                  int rows, float *y, nbrdf_error *err);

/* Starts a writer holding every tensor of `nn` (borrowed: keep nn alive until
 * the save) and the common metadata. */
nbrdf_status model_net_writer(const nn_network *nn, const char *network, int latent_dim,
                              nn_st_writer **out, nbrdf_error *err);

/* Checks the common metadata of an open file (network kind, format, version)
 * and builds the network it describes, with its weights; *latent_dim gets the
 * file's latent dimension. */
nbrdf_status model_net_read(const nn_st_reader *reader, const char *network, nn_network **out,
                            int *latent_dim, nbrdf_error *err);

/* Fails unless the file says it holds `network` (nbrdf.format and
 * nbrdf.network), so that a file in the wrong place gets that message first. */
nbrdf_status model_net_check_kind(const nn_st_reader *reader, const char *network,
                                  nbrdf_error *err);

/* Integer metadata value in [lo, hi]; the message names the file and key. */
nbrdf_status model_meta_int(const nn_st_reader *reader, const char *key, long lo, long hi,
                            long *value, nbrdf_error *err);
/* Finite double metadata value in [lo, hi]. */
nbrdf_status model_meta_double(const nn_st_reader *reader, const char *key, double lo, double hi,
                               double *value, nbrdf_error *err);

#endif
