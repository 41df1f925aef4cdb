#!/usr/bin/env bash
# Research note 2026-11-26, part 3 (issue 18): models/default's layering network retrained
# from scratch on more two-layer Table-2 data, with models/default's decoder and tables
# (paper preset, decoded loss, no energy term: default's recipe, only the data grows), then
# fine-tuned with three-layer data as scripts/train-default.sh does; evaluated on the same
# 20 `layer` / `layer3` BRDFs as the earlier parts (references cached in data/evalcache).
#
#   [L2=7000 L3=1500 TAG=] bash docs/notes/scripts/ladder-and-energy/layering_table2_more_data.sh
#
# Data (resumable; a record is a pure function of seed and index, so the first 3,000
# two-layer and 300 three-layer records are models/default's own):
#   data/layered2-table2-x.nbds   two-layer, seed 1, L2 records
#   data/layered2b-table2.nbds    two-layer, seed 2, 200 records
#   data/layered3-table2.nbds     three-layer, seed 3, L3 records
# The two-layer training and the three-layer data generation run side by side (one core
# each). Writes to $OUT (/tmp/e18).
set -euo pipefail
cd "$(dirname "$0")/../../../.."  # the checkout this script belongs to
N=build/nbrdf
L2=${L2:-7000}
L3=${L3:-1500}
out=${OUT:-/tmp/e18}/t2-$L2-$L3${TAG:-}
mkdir -p "$out"
export OPENBLAS_NUM_THREADS=1
stage() { echo "== $(date -u +%H:%M:%S) $*"; }
d2=data/layered2-table2-x.nbds d2b=data/layered2b-table2.nbds d3=data/layered3-table2.nbds
args=(--loss decoded --preset paper --decoder models/default/decoder.safetensors
  --tables models/default/base_tables.safetensors)

stage "data: $L2 two-layer (seed 1)"
$N dataset --out $d2 --kind layered2 --count "$L2" --seed 1 --threads 0 >/dev/null
(
  $N dataset --out $d2b --kind layered2 --count 200 --seed 2 --threads 1 >/dev/null 2>&1
  $N dataset --out $d3 --kind layered3 --count "$L3" --seed 3 --threads 1 >/dev/null 2>&1
) &
gen=$!
if [ ! -f "$out/layering-2layer.safetensors" ]; then
  stage "layering, two layers, 300 epochs"
  $N train layering "${args[@]}" --data "$d2:$L2" --epochs 300 --decay-every 100 \
    --checkpoint "$out/l2.ckpt" -o "$out/layering-2layer.safetensors" --log "$out/l2.csv" 2>/dev/null
fi
stage "waiting for the three-layer data"
wait $gen
if [ ! -f "$out/layering.safetensors" ]; then
  stage "layering, fine-tuned with three layers, 150 epochs"
  $N train layering "${args[@]}" --init "$out/layering-2layer.safetensors" \
    --data "$d2:$L2,$d2b,$d3:$L3" --epochs 150 --lr 5e-4 --decay-every 50 \
    --checkpoint "$out/l3.ckpt" -o "$out/layering.safetensors" --log "$out/l3.csv" 2>/dev/null
fi
for net in layering-2layer layering; do
  rm -rf "$out/bundle-$net"
  $N train bundle -o "$out/bundle-$net" --name "t2-$L2-$net" \
    --decoder models/default/decoder.safetensors --tables models/default/base_tables.safetensors \
    --layering "$out/$net.safetensors" --sampler models/default/sampler.safetensors
  stage "evaluate $net"
  $N evaluate --bundle "$out/bundle-$net" --sets layer,layer3 --count 20 --walks 2000 \
    --noise-brdfs 3 --cache data/evalcache --json "$out/eval-$net.json" >"$out/eval-$net.txt" 2>&1
done
stage done
