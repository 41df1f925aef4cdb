#!/usr/bin/env bash
# The size axis of the equal-compute comparison (run.sh's small and large points, resumed).
cd "$(dirname "$0")/../../../.."  # the checkout this script belongs to
export OPENBLAS_NUM_THREADS=1
n=runs/cmp/nbrdf
data=data/single.nbds:3000,data/layered2.nbds:1700
$n train decoder --data $data --run runs/cmp/small --steps 7600 --validation 0 --seed 1 --width 32 --blocks 2 --progress=json > runs/cmp/small.out 2> runs/cmp/small.err &
$n train decoder --data $data --run runs/cmp/large --steps 393 --validation 0 --seed 1 --width 128 --blocks 3 --progress=json > runs/cmp/large.out 2> runs/cmp/large.err &
wait
echo done > runs/cmp/done2
