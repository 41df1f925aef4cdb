/* Prints the parameters of the first N BRDFs of the held-out `layer` set
 * (docs/METRICS.md) as `nbrdf bake` arguments, one BRDF a line, for the
 * constant bakes of bench/ladder_trade.sh. Usage: bench_heldout_params [N] */
#include <stdio.h>
#include <stdlib.h>

#include "train/params.h"

int main(int argc, char **argv) {
  int n = argc > 1 ? atoi(argv[1]) : 50;
  uint64_t family = train_heldout_seed(TRAIN_HELDOUT_LAYER);
  for (int k = 0; k < n; k++) {
    train_params p;
    train_params_draw(family, train_heldout_kind(TRAIN_HELDOUT_LAYER), (uint64_t)k, &p);
    printf("%d --alpha1 %.6g --eta %.6g --alpha2 %.6g --r0 %.6g --albedo %.6g --sigma-t %.6g\n", k,
           p.coat[0].alpha, p.coat[0].eta, p.base_alpha, p.base_r0, p.coat[0].albedo,
           p.coat[0].sigma_t);
  }
  return 0;
}
