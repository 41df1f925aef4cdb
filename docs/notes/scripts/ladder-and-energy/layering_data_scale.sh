#!/usr/bin/env bash
# Research note 2026-11-26, part 2 (issue 18): the layering network trained from scratch
# (paper preset, decoded loss) on the first N coverage two-layer BRDFs, evaluated on 20
# `layer` BRDFs: how its error scales with data.
#   [EPOCHS=300 DECAY=100 TAG=] bash docs/notes/scripts/ladder-and-energy/layering_data_scale.sh N   (1500, 3000)
# Needs data/layered2-coverage.nbds (scripts/train-default.sh); writes to $OUT (/tmp/e18).
set -euo pipefail
cd "$(dirname "$0")/../../../.."  # the checkout this script belongs to
N=build/nbrdf; n=$1; out=${OUT:-/tmp/e18}/scale$n${TAG:-}; mkdir -p $out
export OPENBLAS_NUM_THREADS=1
$N train layering --loss decoded --preset paper --decoder models/default/decoder.safetensors \
  --tables models/default/base_tables.safetensors --data data/layered2-coverage.nbds:$n \
  --epochs ${EPOCHS:-300} --decay-every ${DECAY:-100} --checkpoint $out/l.ckpt -o $out/layering.safetensors --log $out/l.csv
rm -rf $out/bundle
$N train bundle -o $out/bundle --name scale$n --decoder models/default/decoder.safetensors \
  --tables models/default/base_tables.safetensors --layering $out/layering.safetensors \
  --sampler models/default/sampler.safetensors
$N evaluate --bundle $out/bundle --sets layer --count 20 --walks 2000 --noise-brdfs 3 \
  --cache data/evalcache --json $out/eval.json > $out/eval.txt 2>&1
echo done
