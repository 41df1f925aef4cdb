/* Training data for the decoder: ground-truth values of BRDFs drawn
 * from Table 2 (train/params.h) at direction pairs that cover sharp lobes.
 * The file format is documented in docs/DATASET.md.
 *
 * Per BRDF k (a pure function of (seed, k), so any thread count gives the
 * same bytes and an interrupted file can be resumed):
 * - K incident directions, θi stratified over [0°, 89°) (one jittered θ per
 *   stratum), φi = 0 (the BRDFs are isotropic);
 * - M outgoing directions per ωi: the first M − S alternate uniform and
 *   cosine-weighted hemisphere directions, the last S are importance-sampled
 *   from the BRDF (nbrdf_brdf_sample; a draw that leaves no direction falls
 *   back to a cosine direction);
 * - values f(ωi, ωo) without cosine and their standard errors: analytic (error
 *   0) for single BRDFs, the whole-lobe estimator (brdf/layered_lobe.h, `spp`
 *   walks per ωi shared by its M directions) for layered ones. */
#ifndef NBRDF_TRAIN_DATASET_H
#define NBRDF_TRAIN_DATASET_H

#include <stddef.h>
#include <stdint.h>

#include "brdf/layered_lobe.h"
#include "nbrdf/status.h"
#include "train/dataset_settings.h"
#include "train/params.h"

/* One BRDF's record as stored. samples: incident·outgoing × 8 floats. */
typedef struct train_dataset_record {
  uint64_t index;
  train_params params;
  size_t n_samples;
  const float *samples;
} train_dataset_record;

/* Checks the ranges of the settings (count aside). */
nbrdf_status train_dataset_check_settings(const train_dataset_settings *s, nbrdf_error *err);

/* Fills the samples of BRDF `index` (incident·outgoing·8 floats) and its
 * parameters; single-threaded, a pure function of (settings, index). A
 * layered BRDF's random walks ask `hook` (may be NULL) between chunks, and
 * NBRDF_ERR_CANCELLED is returned (samples undefined) when it says stop. */
nbrdf_status train_dataset_generate_one(const train_dataset_settings *s, uint64_t index,
                                        const brdf_layered_lobe_hook *hook, train_params *params,
                                        float *samples, nbrdf_error *err);

/* The samples of any BRDF `params` (not necessarily a Table 2 draw: base-latent
 * tables and held-out sets use it), with the random streams of (family, index):
 * a pure function of its arguments. */
nbrdf_status train_samples_generate(const train_dataset_settings *s, uint64_t family,
                                    uint64_t index, const train_params *params, float *samples,
                                    nbrdf_error *err);

/* As train_samples_generate, under a hook (may be NULL): NBRDF_ERR_CANCELLED
 * when the walks are stopped (the samples then undefined). */
nbrdf_status train_samples_generate_hooked(const train_dataset_settings *s, uint64_t family,
                                           uint64_t index, const train_params *params,
                                           const brdf_layered_lobe_hook *hook, float *samples,
                                           nbrdf_error *err);

/* Writes (or resumes) the data set at `path`. If the file exists, its header
 * must match the settings (else NBRDF_ERR_MISMATCH); its valid records are
 * kept, a trailing partial or corrupt record is dropped, and generation goes
 * on from there; a complete file is left as is. When the progress callback
 * asks to stop, the records written so far stay (NBRDF_ERR_CANCELLED): the
 * same call resumes. *resumed_from (may be NULL) receives the number of
 * records kept from an existing file. */
nbrdf_status train_dataset_write(const char *path, const train_dataset_settings *s,
                                 uint64_t *resumed_from, nbrdf_error *err);

/* What train_dataset_read found. */
typedef struct train_dataset_info {
  train_dataset_settings settings; /* from the header (threads, progress: 0) */
  uint64_t records;                /* valid records */
  int complete;                    /* all `count` records and a valid footer */
  uint64_t checksum;               /* the footer's checksum (0 if incomplete) */
  uint64_t valid_bytes;            /* header + valid records */
  uint64_t prefix_checksum;        /* running checksum over those bytes */
} train_dataset_info;

/* Called for each valid record in order; return non-zero to stop reading. */
typedef int (*train_dataset_record_fn)(void *user, const train_dataset_record *r);

/* Reads and validates `path`: header, every record's checksum, index and
 * parameters (they must be those the header's seed draws), every sample
 * (unit directions with z > 0, finite f ≥ 0, finite error ≥ 0), and the
 * footer's whole-file checksum. Stops at the first invalid record: with
 * `strict` that is an error naming the record, otherwise the prefix is
 * reported as valid (info->records) and complete = 0. on_record may be NULL. */
nbrdf_status train_dataset_read(const char *path, int strict, train_dataset_info *info,
                                train_dataset_record_fn on_record, void *user, nbrdf_error *err);

#endif
