/* Layering training (paper §4): the layering network learns to map (table
 * latent of the top dielectric, table latent of the bottom conductor, A, σT)
 * to the latent of that two-layer BRDF. Inputs are looked up in the base
 * tables exactly as a bake does (train/layering_pairs.h), so the network also
 * absorbs the tables' interpolation error. Two losses:
 *
 * - latent (train_layering_fit): mean squared error to the latent the
 *   auto-decoder learned for the BRDF (the paper's loss). Needs the decoder
 *   run's latents, so only BRDFs the decoder was trained on serve.
 * - decoded (train_layering_fit_decoded): the decoder's own loss (loss.h) of
 *   the decoded output against the BRDF's ground-truth samples, the decoder
 *   frozen and back-propagated through into the layering network. Any two-layer
 *   BRDF with samples serves, and the network is free to choose any latent
 *   that decodes well instead of the one the auto-decoder happened to pick.
 *
 * One pair in `validation_every` is held out; for both losses the decoded
 * validation loss (val_decoded) is measured on all its samples, so the two
 * compare end to end. */
#ifndef NBRDF_TRAIN_LAYERING_H
#define NBRDF_TRAIN_LAYERING_H

#include "model/base_table.h"
#include "model/decoder.h"
#include "model/energy.h"
#include "model/layering.h"
#include "model/loss.h"
#include "train/checkpoint.h"
#include "train/layering_settings.h"
#include "train/layering_pairs.h"
#include "train/samples.h"

/* `data` and `latents` [data->n_brdfs × D] are the decoder run's BRDFs and
 * their learned latents; its two-layer BRDFs become the training pairs.
 * `dec` (may be NULL) only measures val_decoded. *out is created here. */
nbrdf_status train_layering_fit(const train_samples *data, const float *latents, model_decoder *dec,
                                const model_base_table tables[2], const train_layering_settings *s,
                                model_layering **out, train_layering_result *r, nbrdf_error *err);

/* The decoded loss. `dec` (borrowed, not modified) must be the decoder the
 * tables were made for. With s->checkpoint, a run resumes from it (same data,
 * preset and settings) and writes it every s->checkpoint_seconds and at the
 * end; every step is a pure function of (seed, epoch, step), so a resumed run
 * equals an uninterrupted one. Cancelling (progress callback) checkpoints. */
nbrdf_status train_layering_fit_decoded(const train_samples *data, model_decoder *dec,
                                        const model_base_table tables[2],
                                        const train_layering_settings *s, model_layering **out,
                                        train_layering_result *r, nbrdf_error *err);

/* Mean decoded loss over all samples of `pairs` (their BRDFs in `data`), the
 * latents coming from `net` (or, if net is NULL, from pairs->target). */
nbrdf_status train_layering_decoded_loss(const model_layering *net, model_decoder *dec,
                                         model_loss_kind loss, const train_samples *data,
                                         const train_layering_pairs *pairs, double *mean,
                                         nbrdf_error *err);

/* A hash of both tables' axes and latents (checkpoint options). */
uint64_t train_layering_tables_hash(const model_base_table tables[2]);

/* The network's latent for every pair (recursive for three layers), out
 * [p->n × D]: what a bake computes for those parameters. */
nbrdf_status train_layering_pair_latents(const model_layering *net, const train_layering_pairs *p,
                                         float *out, nbrdf_error *err);

/* The gradient engine of the decoded loss (the fit's inner step; exposed for
 * the gradient check). `net`, `dec`, `data` are borrowed. */
typedef struct train_layering_decoded train_layering_decoded;
nbrdf_status train_layering_decoded_create(model_layering *net, model_decoder *dec,
                                           const train_samples *data, int batch, int rows,
                                           model_loss_kind loss, uint64_t seed,
                                           train_layering_decoded **out, nbrdf_error *err);
void train_layering_decoded_destroy(train_layering_decoded *t);
/* Adds the energy penalty to every later gradient (λ = 0: none). */
nbrdf_status train_layering_decoded_set_energy(train_layering_decoded *t,
                                               const model_energy_options *o, int brdfs_per_batch,
                                               nbrdf_error *err);
/* Loss of m <= batch pairs idx[] of p, `rows` samples each drawn from PCG32
 * stream `step` (a step does not depend on what ran before it), and its
 * gradient with respect to the layering weights ADDED into grad. */
nbrdf_status train_layering_decoded_gradient(train_layering_decoded *t,
                                             const train_layering_pairs *p, const size_t *idx,
                                             int m, int64_t step, float *grad, double *loss,
                                             nbrdf_error *err);

#endif
