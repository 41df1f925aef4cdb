#!/usr/bin/env bash
# Cartesian encoding with and without --brdf-weight 0.5 at the equal-compute budget (1,500 steps).
cd "$(dirname "$0")/../../../.."  # the checkout this script belongs to
export OPENBLAS_NUM_THREADS=1
n=runs/bw/nbrdf
data=data/single.nbds:3000,data/layered2.nbds:1700
ev() { $n evaluate --decoder $2 --sets rep,single --count 100 --walks 2000 --cache data/evalcache --json runs/bw/$1-eval.json > runs/bw/$1-eval.out 2>/dev/null
  echo "$1 $(grep -E '^(rep|single)' runs/bw/$1-eval.out | tr '\n' ' ')" >> runs/bw/summary.txt; }
$n train decoder --data $data --run runs/bw/cart-w05 --steps 1500 --validation 0 --seed 1 --width 64 --blocks 3 --encoding cartesian --brdf-weight 0.5 --progress=json > /dev/null 2> runs/bw/cart-w05.err
ev cart-w05 runs/bw/cart-w05/decoder.safetensors
ev cart-baseline runs/cmp/cartesian/decoder.safetensors
