#!/usr/bin/env bash
# Stages 3-7 of scripts/train-default.sh (tables, layering 2-layer + fine-tune, sampler,
# bundle, evaluation) on this machine's existing data and a finished decoder run.
#   bash docs/notes/scripts/decoder-compare/chain.sh WORK DECODER_RUN "TABLE ARGS"
set -euo pipefail
cd "$(dirname "$0")/../../../.."  # the checkout this script belongs to
export OPENBLAS_NUM_THREADS=1
work=$1 run=$2 targs=$3
nbrdf=$work/nbrdf
stage() { echo "== $(date -u +%H:%M:%S) $*"; }
[ -f "$work/base_tables.safetensors" ] || { stage tables; $nbrdf train tables --decoder "$run/decoder.safetensors" -o "$work/base_tables.safetensors" $targs; }
layer_args=(--loss decoded --preset paper --decoder "$run/decoder.safetensors" --tables "$work/base_tables.safetensors")
if [ ! -f "$work/layering-2layer.safetensors" ]; then
  stage "layering 2-layer"
  $nbrdf train layering "${layer_args[@]}" --data data/layered2.nbds --epochs 300 \
    --decay-every 100 --checkpoint "$work/layering-2layer.ckpt" \
    -o "$work/layering-2layer.safetensors" --log "$work/layering-2layer.csv" --progress=json 2> "$work/l2.err"
fi
if [ ! -f "$work/layering.safetensors" ]; then
  stage "layering fine-tune"
  $nbrdf train layering "${layer_args[@]}" --init "$work/layering-2layer.safetensors" \
    --data data/layered2.nbds,data/layered2b.nbds:200,data/layered3.nbds \
    --epochs 150 --lr 5e-4 --decay-every 50 --checkpoint "$work/layering.ckpt" \
    -o "$work/layering.safetensors" --log "$work/layering.csv" --progress=json 2> "$work/l3.err"
fi
if [ ! -f "$work/sampler.safetensors" ]; then
  stage sampler
  $nbrdf train sampler --run "$run" -o "$work/sampler.safetensors" \
    --layering "$work/layering.safetensors" --tables "$work/base_tables.safetensors" \
    --data data/layered2.nbds,data/layered2b.nbds:200,data/layered3.nbds 2> "$work/s.err"
fi
stage bundle
rm -rf "$work/bundle"
$nbrdf train bundle -o "$work/bundle" --name default --decoder "$run/decoder.safetensors" \
  --tables "$work/base_tables.safetensors" --layering "$work/layering.safetensors" \
  --sampler "$work/sampler.safetensors" --card docs/MODEL_CARD_DEFAULT.md --note "candidate"
stage evaluate
$nbrdf evaluate --bundle "$work/bundle" --sets rep,single,layer,layer3,table --count 100 --walks 2000 \
  --cache data/evalcache --json "$work/evaluation.json" --plots "$work/eval-plots" 2>/dev/null | tee "$work/eval.out"
stage done
