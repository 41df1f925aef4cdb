/* Sampling-network training (paper §5). The proxy of Eq. 6 has two
 * per-latent constants (σ, w), so training splits in two:
 *  1. per latent, (σ, w) minimising the cross-entropy −E_p*[log q] between
 *     the decoded BRDF's normalised outgoing radiance p*(ωo | ωi) ∝ f cos θo
 *     (averaged over incident directions, as the paper's GNDF target) and
 *     the proxy q — the KL divergence of Eq. 8 up to p*'s own entropy. The
 *     expectation is estimated with ωo drawn from a wide fixed proxy
 *     (importance weights f cos θo / q0); w is a convex 1-D problem for each σ,
 *     σ a golden-section search in log σ;
 *  2. the network regresses the raw outputs (o0, o1) that give those (σ, w)
 *     through model/sampler.h's transform (mean squared error), so that it
 *     generalises to latents made by layering at bake time.
 * The per-latent optimum is what a network with unlimited capacity would
 * reach under the KL loss; fitting it directly costs seconds, not hours. */
#ifndef NBRDF_TRAIN_SAMPLER_H
#define NBRDF_TRAIN_SAMPLER_H

#include <signal.h>
#include <stdint.h>

#include "model/decoder.h"
#include "model/sampler.h"

typedef struct train_sampler_settings {
  int incident, outgoing; /* ωi per latent (θi stratified in [0, 80°]) × ωo per ωi */
  int epochs, batch;
  float lr;
  uint64_t seed;
  nbrdf_progress_fn progress; /* stages "sampler: targets", "sampler: network" */
  void *user;
  /* The network's training (train/trainer.h): */
  const char *checkpoint;        /* resumable state, written atomically (may be NULL) */
  double checkpoint_seconds;     /* at most this long between checkpoints */
  double max_seconds;            /* stop (checkpointed) after this long; 0 = no limit */
  int64_t stop_at_step;          /* stop (checkpointed) after this many batches; 0 = none */
  volatile sig_atomic_t *cancel; /* may be NULL */
} train_sampler_settings;

#define TRAIN_SAMPLER_SETTINGS_DEFAULT                                                             \
  { 6, 256, 300, 128, 1e-3f, 1u, NULL, NULL, NULL, 300.0, 0.0, 0, NULL }

typedef struct train_sampler_result {
  double mean_ce_fit, mean_ce_cosine; /* cross-entropy of the fitted proxy vs w = 1 (cosine) */
  double rms_o;                       /* network's RMS error on the raw outputs (all latents) */
  int64_t resumed_from;               /* batches done before this call (0: a fresh run) */
} train_sampler_result;

/* Per-latent optimal (σ, w) of n latents [n × D] under decoder `dec`. */
nbrdf_status train_sampler_targets(model_decoder *dec, size_t n, const float *latents,
                                   const train_sampler_settings *s, float *sigma, float *w,
                                   double *mean_ce_fit, double *mean_ce_cosine, nbrdf_error *err);

/* Both steps; *out is created here. With s->checkpoint the network's
 * training resumes from it (same settings, latents and decoder) and writes it
 * every s->checkpoint_seconds, on a stop and at the end. */
nbrdf_status train_sampler_fit(model_decoder *dec, size_t n, const float *latents,
                               const train_sampler_settings *s, model_sampler **out,
                               train_sampler_result *r, nbrdf_error *err);

#endif
