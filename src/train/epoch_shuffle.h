/* The per-epoch shuffles of the epoch-based fits, of two kinds (a fit's kind
 * is part of what its results for a seed are: switching changes them):
 *  - carried (the latent-loss layering, the sampler network): drawn from one
 *    generator carried across epochs, made resumable: the checkpoint keeps
 *    the generator's state before the current epoch's shuffle
 *    (train_epoch_shuffle_words), and a run resumed inside an epoch draws
 *    that epoch's shuffle again;
 *  - per epoch (the decoded-loss layering): epoch e's shuffle drawn from its
 *    own stream (stream + e) of the seed, a function of the seed and the
 *    epoch alone, so a checkpoint keeps nothing for it. */
#ifndef NBRDF_TRAIN_EPOCH_SHUFFLE_H
#define NBRDF_TRAIN_EPOCH_SHUFFLE_H

#include <stddef.h>
#include <stdint.h>

#include "core/rng.h"
#include "train/trainer.h"

typedef struct train_epoch_shuffle {
  size_t *idx; /* [n]: the shuffle of epoch shuffled − 1 */
  size_t n;
  core_rng before, after; /* around that shuffle */
  uint64_t shuffled;      /* epochs shuffled so far */
  int valid;              /* idx holds that shuffle (0 after a resume) */
  int per_epoch;          /* the per-epoch kind: streams stream + e of seed */
  uint64_t seed, stream;
} train_epoch_shuffle;

/* idx = a Fisher–Yates shuffle of 0..n−1 drawn from g (advanced). */
void train_shuffle_indices(size_t *idx, size_t n, core_rng *g);

/* Allocates idx (returns 0 when out of memory); the carried kind: the
 * generator starts at (seed, stream). */
int train_epoch_shuffle_init(train_epoch_shuffle *s, size_t n, uint64_t seed, uint64_t stream);
/* The per-epoch kind: epoch e's shuffle from stream `stream` + e of seed. */
int train_epoch_shuffle_init_per_epoch(train_epoch_shuffle *s, size_t n, uint64_t seed,
                                       uint64_t stream);
void train_epoch_shuffle_free(train_epoch_shuffle *s);
/* The shuffle of `epoch` (the carried kind: epochs only move forward). */
const size_t *train_epoch_shuffle_get(train_epoch_shuffle *s, uint64_t epoch);
/* The 3 words a checkpoint keeps (the carried kind). */
void train_epoch_shuffle_words(train_epoch_shuffle *s, trainer_word words[3]);

#endif
