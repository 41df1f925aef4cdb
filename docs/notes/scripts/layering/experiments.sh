#!/usr/bin/env bash
# The layering comparison of docs/notes/2026-11-22-training-experiments.md ("Layering: latent vs decoded loss"), as run on
# 2026-11-22 with models/default's decoder and tables (data from scripts/train-default.sh).
# Each run then: nbrdf train bundle (those parts + the run's layering) and
# nbrdf evaluate --sets layer --count 100 --walks 2000 --cache data/evalcache.
set -euo pipefail
here=$PWD
cd "$(dirname "$0")/../../../.."  # the checkout this script belongs to
# A path the caller gives ($NBRDF, the output folder) is relative to where it ran.
abs() { case $1 in /*) echo "$1" ;; *) echo "$here/$1" ;; esac; }
export OPENBLAS_NUM_THREADS=1
n=build/nbrdf
case ${NBRDF:-} in "") ;; */*) n=$(abs "$NBRDF") ;; *) n=$NBRDF ;; esac # a bare name: on PATH
D="--decoder models/default/decoder.safetensors --tables models/default/base_tables.safetensors"
w=runs/lay-dec
if [ $# -ge 1 ]; then w=$(abs "$1"); fi
mkdir -p "$w"
# latent loss on the decoder run's pairs, 80 epochs: models/default's network (bit-identical)
$n train layering --loss latent --data data/single.nbds:3000,data/layered2.nbds:1700 \
  --run data/decoder-run --tables models/default/base_tables.safetensors --epochs 80 \
  -o $w/latent80.safetensors --log $w/latent80.csv
# decoded loss, small preset: from the latent network, and from scratch
$n train layering --loss decoded --data data/layered2.nbds $D --init $w/latent80.safetensors \
  --epochs 300 --decay-every 100 -o $w/dec-init.safetensors --log $w/dec-init.csv --checkpoint $w/dec-init.ckpt
$n train layering --loss decoded --data data/layered2.nbds $D --epochs 300 --decay-every 100 \
  -o $w/dec-scratch.safetensors --log $w/dec-scratch.csv --checkpoint $w/dec-scratch.ckpt
# decoded loss, medium and paper presets, from scratch
for p in medium paper; do
  $n train layering --loss decoded --preset $p --data data/layered2.nbds $D --epochs 300 \
    --decay-every 100 -o $w/dec-$p.safetensors --log $w/dec-$p.csv --checkpoint $w/dec-$p.ckpt
done
