/* Per-epoch shuffles drawn from one generator carried across epochs (the
 * latent-loss layering and the sampler network, as they always drew them),
 * made resumable: the checkpoint keeps the generator's state before the
 * current epoch's shuffle (train_epoch_shuffle_words), and a run resumed
 * inside an epoch draws that epoch's shuffle again. */
#ifndef NBRDF_TRAIN_EPOCH_SHUFFLE_H
#define NBRDF_TRAIN_EPOCH_SHUFFLE_H

#include <stddef.h>
#include <stdint.h>

#include "core/rng.h"
#include "train/trainer.h"

typedef struct train_epoch_shuffle {
  size_t *idx; /* [n]: the shuffle of epoch shuffled − 1 */
  size_t n;
  core_rng before, after;  /* around that shuffle */
  uint64_t shuffled;       /* epochs shuffled so far */
  int valid;               /* idx holds that shuffle (0 after a resume) */
} train_epoch_shuffle;

/* idx = a Fisher–Yates shuffle of 0..n−1 drawn from g (advanced). */
void train_shuffle_indices(size_t *idx, size_t n, core_rng *g);

/* Allocates idx; the generator starts at (seed, stream). */
int train_epoch_shuffle_init(train_epoch_shuffle *s, size_t n, uint64_t seed, uint64_t stream);
void train_epoch_shuffle_free(train_epoch_shuffle *s);
/* The shuffle of `epoch` (epochs only move forward). */
const size_t *train_epoch_shuffle_get(train_epoch_shuffle *s, uint64_t epoch);
/* The 3 words a checkpoint keeps. */
void train_epoch_shuffle_words(train_epoch_shuffle *s, trainer_word words[3]);

#endif
