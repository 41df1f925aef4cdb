#!/usr/bin/env bash
# Decoder trade at the shipped budget (14,342 steps, the shipped recipe): cartesian encoding
# at the medium size, and the small size; one OpenBLAS thread each, niced. The cartesian
# figures come from `c`: the earlier 5,370-step cartesian run (runs/cmp-cartesian, same
# settings) copied to runs/conv/cart-resume and resumed to 14,342 steps.
cd "$(dirname "$0")/../../../.."  # the checkout this script belongs to
export OPENBLAS_NUM_THREADS=1
n=runs/conv/nbrdf
data=data/single.nbds:3000,data/layered2.nbds:1700
one() { # name args...
  local name=$1; shift
  local t0=$(date +%s)
  $n train decoder --data $data --run runs/conv/$name --steps 14342 --decay-every 5000 --seed 1 "$@" --progress=json > runs/conv/$name.out 2> runs/conv/$name.err
  local t1=$(date +%s)
  $n evaluate --decoder runs/conv/$name/decoder.safetensors --sets rep,single --count 100 --walks 2000 --cache data/evalcache --json runs/conv/$name-eval.json > runs/conv/$name-eval.out 2>/dev/null
  echo "$name train_s=$((t1 - t0)) $(tail -3 runs/conv/$name-eval.out | tr '\n' ' ')" >> runs/conv/summary.txt
}
case $1 in
  a) one cartesian --width 64 --blocks 3 --encoding cartesian ;;
  c) one cart-resume --width 64 --blocks 3 --encoding cartesian ;;
  b) one small --preset small ;;
esac
