#!/usr/bin/env bash
# Per-BRDF loss weights (--brdf-weight P) at the equal-compute budget of runs/cmp
# (medium size, 1,500 steps, same data, seed and schedule, --validation 0).
cd "$(dirname "$0")/../../../.."  # the checkout this script belongs to
export OPENBLAS_NUM_THREADS=1
n=runs/bw/nbrdf
data=data/single.nbds:3000,data/layered2.nbds:1700
ev() { # name decoder
  $n evaluate --decoder $2 --sets rep,single --count 100 --walks 2000 --cache data/evalcache --json runs/bw/$1-eval.json > runs/bw/$1-eval.out 2>/dev/null
  echo "$1 $(grep -E '^(rep|single)' runs/bw/$1-eval.out | tr '\n' ' ')" >> runs/bw/summary.txt
}
one() { # name P
  local t0=$(date +%s)
  $n train decoder --data $data --run runs/bw/$1 --steps 1500 --validation 0 --seed 1 --width 64 --blocks 3 --brdf-weight $2 --progress=json > runs/bw/$1.out 2> runs/bw/$1.err
  echo "$1 train_s=$(( $(date +%s) - t0 ))" >> runs/bw/summary.txt
  ev $1 runs/bw/$1/decoder.safetensors
}
ev medium-baseline runs/cmp/medium/decoder.safetensors
one w05 0.5
one w1 1
