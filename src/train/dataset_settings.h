/* The settings of a training dataset: what its header records
 * (dataset_format.c) and what generating it takes (dataset.c). */
#ifndef NBRDF_TRAIN_DATASET_SETTINGS_H
#define NBRDF_TRAIN_DATASET_SETTINGS_H

#include <stdint.h>

#include "nbrdf/status.h"
#include "train/params.h"

/* Version 1: Table 2 draws; version 2 adds the draw distribution (params.h),
 * written only for non-Table 2 sets, so Table 2 files stay version 1 byte for
 * byte. Both are read. */
#define TRAIN_DATASET_VERSION 1u
#define TRAIN_DATASET_VERSION_DRAWS 2u
#define TRAIN_DATASET_PARAMS 11 /* doubles per parameter record */
#define TRAIN_DATASET_FLOATS 8  /* floats per sample: wi[3], wo[3], f, f_stderr */

typedef struct train_dataset_settings {
  train_kind kind;
  uint64_t count; /* BRDFs */
  uint64_t seed;  /* user seed (train_family_seed(seed) draws the BRDFs) */
  int incident;   /* K, incident directions per BRDF */
  int outgoing;   /* M, outgoing directions per incident direction */
  int sampled;    /* S ≤ M of them importance-sampled from the BRDF */
  int spp;        /* whole-lobe walks per incident direction (layered; ≥ 2) */
  int threads;    /* 0 = all (OpenMP); never changes the output */
  /* Stage "dataset", done/total in BRDFs, at most ~10 times a second, also
   * between the BRDFs of a batch; a non-zero return stops after the BRDFs
   * in progress (the file keeps every finished one, in order; resumable).
   * May be NULL. */
  nbrdf_progress_fn progress;
  void *user;
  train_draws draws; /* parameter distribution (params.h); TABLE2 by default */
} train_dataset_settings;

#define TRAIN_DATASET_SETTINGS_DEFAULT                                                             \
  { TRAIN_LAYERED2, 0, 0, 8, 128, 64, 2048, 0, NULL, NULL, TRAIN_DRAWS_TABLE2 }

#endif
