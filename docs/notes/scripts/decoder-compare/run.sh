#!/usr/bin/env bash
# Decoder comparison at equal compute: steps x MACs per query = 1500 x 27,072 (the medium
# preset's 1500 steps); same data, seed, schedule; one OpenBLAS thread each, two at a time.
cd "$(dirname "$0")/../../../.."  # the checkout this script belongs to
export OPENBLAS_NUM_THREADS=1
n=runs/cmp/nbrdf
data=data/single.nbds:3000,data/layered2.nbds:1700
one() { # name steps args...
  local name=$1 steps=$2; shift 2
  local t0=$(date +%s)
  $n train decoder --data $data --run runs/cmp/$name --steps $steps --validation 0 --seed 1 "$@" --progress=json > runs/cmp/$name.out 2> runs/cmp/$name.err
  local t1=$(date +%s)
  $n evaluate --decoder runs/cmp/$name/decoder.safetensors --sets rep --count 100 --walks 2000 --cache data/evalcache --json runs/cmp/$name-rep.json > runs/cmp/$name-eval.out 2>/dev/null
  echo "$name steps=$steps train_s=$((t1 - t0)) $(tail -1 runs/cmp/$name-eval.out)" >> runs/cmp/summary.txt
}
q1() {
  one medium 1500 --width 64 --blocks 3
  one cartesian 1500 --width 64 --blocks 3 --encoding cartesian
  one small 7600 --width 32 --blocks 2
}
q2() {
  one paper-loss 1500 --width 64 --blocks 3 --output f --loss l1
  one octaves2 1500 --width 64 --blocks 3 --octaves 2
  one large 393 --width 128 --blocks 3
}
q1 & q2 & wait
echo done > runs/cmp/done
