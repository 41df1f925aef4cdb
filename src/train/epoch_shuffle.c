#include "train/epoch_shuffle.h"

#include <stdlib.h>

int train_epoch_shuffle_init(train_epoch_shuffle *s, size_t n, uint64_t seed, uint64_t stream) {
  s->n = n;
  s->idx = malloc((n ? n : 1) * sizeof *s->idx);
  core_rng_init(&s->before, seed, stream);
  s->after = s->before;
  s->shuffled = 0;
  s->valid = 0;
  s->per_epoch = 0;
  s->seed = seed, s->stream = stream;
  return s->idx != NULL;
}

int train_epoch_shuffle_init_per_epoch(train_epoch_shuffle *s, size_t n, uint64_t seed,
                                       uint64_t stream) {
  int ok = train_epoch_shuffle_init(s, n, seed, stream);
  s->per_epoch = 1;
  return ok;
}

void train_epoch_shuffle_free(train_epoch_shuffle *s) {
  free(s->idx);
  s->idx = NULL;
}

void train_shuffle_indices(size_t *idx, size_t n, core_rng *g) {
  for (size_t i = 0; i < n; i++)
    idx[i] = i;
  for (size_t i = n; i > 1; i--) {
    size_t j = (size_t)(core_rng_uniform(g) * (double)i), x = idx[i - 1];
    idx[i - 1] = idx[j], idx[j] = x;
  }
}

static void draw(train_epoch_shuffle *s) {
  core_rng g = s->before;
  train_shuffle_indices(s->idx, s->n, &g);
  s->after = g;
  s->valid = 1;
}

const size_t *train_epoch_shuffle_get(train_epoch_shuffle *s, uint64_t epoch) {
  if (s->per_epoch) {
    if (!s->valid || s->shuffled != epoch + 1) {
      core_rng g;
      core_rng_init(&g, s->seed, s->stream + epoch);
      train_shuffle_indices(s->idx, s->n, &g);
      s->valid = 1;
      s->shuffled = epoch + 1;
    }
    return s->idx;
  }
  if (!s->valid && s->shuffled > 0) draw(s);
  while (s->shuffled < epoch + 1) {
    if (s->shuffled > 0) s->before = s->after;
    draw(s);
    s->shuffled++;
  }
  return s->idx;
}

void train_epoch_shuffle_words(train_epoch_shuffle *s, trainer_word words[3]) {
  words[0] = (trainer_word){"shuffle.state", &s->before.state};
  words[1] = (trainer_word){"shuffle.inc", &s->before.inc};
  words[2] = (trainer_word){"shuffled", &s->shuffled};
}
