/* Training samples in memory: the records of one or more data sets
 * (train/dataset.h) concatenated, grouped by BRDF, in the layout the
 * auto-decoder fit reads (model/autodecoder.h). Standard errors are dropped:
 * the generator keeps them small against the fit's error (docs/DATASET.md). */
#ifndef NBRDF_TRAIN_SAMPLES_H
#define NBRDF_TRAIN_SAMPLES_H

#include <stddef.h>
#include <stdint.h>

#include "model/autodecoder.h"
#include "train/dataset.h"

typedef struct train_samples {
  size_t n_brdfs, n_rows;
  size_t *offsets;      /* n_brdfs + 1 */
  float *wi, *wo, *f;   /* [n_rows × 3], [n_rows × 3], [n_rows] */
  train_params *params; /* per BRDF */
  uint64_t *checksums;  /* per file: the footer checksum (identifies the data) */
  int n_files;
} train_samples;

/* Reads data sets in the given order: "path" must be a complete file (strict
 * validation); "path:N" takes its first N records, which may come from a file
 * still being generated (those records are validated all the same). */
nbrdf_status train_samples_load(int n_files, const char *const *specs, train_samples *out,
                                nbrdf_error *err);
/* Appends one BRDF's interleaved samples (TRAIN_DATASET_FLOATS per sample). */
nbrdf_status train_samples_append(train_samples *s, const train_params *params, size_t n,
                                  const float *samples, nbrdf_error *err);
/* Appends the samples of n BRDFs `params` made by the data-set generator's
 * default settings with the random streams of (family, index k), generated in
 * parallel (each a pure function of its index), in order. */
nbrdf_status train_samples_generate_all(train_samples *s, size_t n, const train_params *params,
                                        uint64_t family, nbrdf_error *err);
void train_samples_free(train_samples *s);

/* The view the fit takes (borrowed). */
model_samples train_samples_view(const train_samples *s);

#endif
