#!/usr/bin/env bash
# Research note 2026-11-26, part 2 (issue 18): models/default's layering network fine-tuned
# on the coverage data with the energy penalty at weight LAMBDA (0: off), bundled with
# default's decoder, tables and sampler, evaluated on 20 `layer` and `layer3` BRDFs.
#   bash docs/notes/scripts/ladder-and-energy/energy_finetune.sh LAMBDA
# Needs data/ from `NBRDF_EVALUATE=0 bash scripts/train-default.sh` (coverage draws: the
# layered*-coverage.nbds files) and writes to $OUT (/tmp/e18); references are cached in
# data/evalcache (first run: about 15 minutes of walks per set).
set -euo pipefail
cd "$(dirname "$0")/../../../.."  # the checkout this script belongs to
N=${NBRDF:-build/nbrdf}
E=$1; tag=e$1
d=data
out=${OUT:-/tmp/e18}/$tag; mkdir -p $out
export OPENBLAS_NUM_THREADS=1
$N train layering --loss decoded --preset paper --decoder models/default/decoder.safetensors \
  --tables models/default/base_tables.safetensors --energy $E --init models/default/layering.safetensors \
  --data $d/layered2-coverage.nbds,$d/layered2b-coverage.nbds,$d/layered3-coverage.nbds \
  --epochs ${EPOCHS:-100} --lr 5e-4 --decay-every 40 --checkpoint $out/l.ckpt -o $out/layering.safetensors --log $out/l.csv
rm -rf $out/bundle
$N train bundle -o $out/bundle --name e18-$tag --decoder models/default/decoder.safetensors \
  --tables models/default/base_tables.safetensors --layering $out/layering.safetensors \
  --sampler models/default/sampler.safetensors
$N evaluate --bundle $out/bundle --sets layer,layer3 --count 20 --walks 2000 --noise-brdfs 3 \
  --cache $d/evalcache --json $out/eval.json > $out/eval.txt 2>&1
echo done
