#!/usr/bin/env bash
# Seed-to-seed spread of the layering network: models/default's decoder and tables, the
# layering stages of scripts/train-default.sh with --seed 2, evaluated on layer and layer3.
set -euo pipefail
cd "$(dirname "$0")/../../../.."  # the checkout this script belongs to
export OPENBLAS_NUM_THREADS=1
w=runs/seed2 n=runs/seed2/nbrdf
args=(--loss decoded --preset paper --decoder models/default/decoder.safetensors --tables models/default/base_tables.safetensors --seed 2)
[ -f $w/l2.safetensors ] || $n train layering "${args[@]}" --data data/layered2.nbds --epochs 300 --decay-every 100 -o $w/l2.safetensors --log $w/l2.csv 2> $w/l2.err
[ -f $w/l.safetensors ] || $n train layering "${args[@]}" --init $w/l2.safetensors --data data/layered2.nbds,data/layered2b.nbds:200,data/layered3.nbds --epochs 150 --lr 5e-4 --decay-every 50 -o $w/l.safetensors --log $w/l.csv 2> $w/l.err
rm -rf $w/bundle
$n train bundle -o $w/bundle --name seed2 --decoder models/default/decoder.safetensors --tables models/default/base_tables.safetensors --layering $w/l.safetensors --sampler models/default/sampler.safetensors
$n evaluate --bundle $w/bundle --sets layer,layer3 --count 100 --walks 2000 --cache data/evalcache --json $w/evaluation.json 2>/dev/null | tee $w/eval.out
