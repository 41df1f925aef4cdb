#!/usr/bin/env bash
# Reproduces models/default from nothing: training data, decoder, base tables,
# layering network, the bundle, and its evaluation on the held-out sets.
# Every stage is resumable: run the script again after an interruption and it
# continues where it stopped (finished stages are skipped). Deterministic by
# seed; OPENBLAS_NUM_THREADS=1 makes the networks' arithmetic bit-reproducible
# (and, measured here, is faster than 2 threads whenever anything else runs:
# OpenBLAS's waiting threads yield their core away). docs/TRAINING.md has the
# recipe, the timings and the figures.
#
#   bash scripts/train-default.sh [WORK_DIR] [BUNDLE_DIR]
#   (defaults: data/ and models/default; NBRDF=path/to/nbrdf to use another build)
set -euo pipefail
cd "$(dirname "$0")/.."
work=${1:-data}
bundle=${2:-models/default}
nbrdf=${NBRDF:-build/nbrdf}
[ -x "$nbrdf" ] || bash scripts/build.sh build >/dev/null
export OPENBLAS_NUM_THREADS=1
mkdir -p "$work"
run="$work/decoder-run"

stage() { echo "== $(date -u +%H:%M:%S) $*"; }

# 1. Ground-truth data (docs/DATASET.md); the counts are the recipe of the shipped model.
stage "data: 3000 single BRDFs"
"$nbrdf" dataset --out "$work/single.nbds" --kind single --count 3000 --seed 1
stage "data: 1700 two-layer BRDFs (~10 min on 2 cores)"
"$nbrdf" dataset --out "$work/layered2.nbds" --kind layered2 --count 1700 --seed 1
data="$work/single.nbds,$work/layered2.nbds"

# 2. Decoder: auto-decoder training, checkpointed every 5 minutes.
stage "decoder (medium preset; resumable)"
"$nbrdf" train decoder --data "$data" --run "$run" --preset medium --steps "${DECODER_STEPS:-14342}" \
  --decay-every 5000 --seed 1

# 3. Base-latent tables by projection with the decoder frozen.
if [ ! -f "$work/base_tables.safetensors" ]; then
  stage "base tables"
  "$nbrdf" train tables --decoder "$run/decoder.safetensors" -o "$work/base_tables.safetensors"
fi

# 4. Layering network on the decoder run's two-layer latents; 80 epochs, where its held-out
#    latent error stops falling (docs/TRAINING.md).
if [ ! -f "$work/layering.safetensors" ]; then
  stage "layering network"
  "$nbrdf" train layering --data "$data" --run "$run" --tables "$work/base_tables.safetensors" \
    -o "$work/layering.safetensors" --log "$work/layering.csv" --epochs 80
fi

# 5. Sampling network: per-latent proxy fits over all the run's latents, then regression.
if [ ! -f "$work/sampler.safetensors" ]; then
  stage "sampling network"
  "$nbrdf" train sampler --run "$run" -o "$work/sampler.safetensors"
fi

# 6. The bundle; its card is docs/MODEL_CARD_DEFAULT.md (the shipped model's figures).
stage "bundle -> $bundle"
"$nbrdf" train bundle -o "$bundle" --name default --decoder "$run/decoder.safetensors" \
  --tables "$work/base_tables.safetensors" --layering "$work/layering.safetensors" \
  --sampler "$work/sampler.safetensors" --card docs/MODEL_CARD_DEFAULT.md \
  --note "trained by scripts/train-default.sh (decoder 14342 steps); measured figures in MODEL_CARD.md"

# 7. Model quality on the held-out sets (references cached in $work/evalcache).
stage "evaluation on the held-out sets"
"$nbrdf" evaluate --bundle "$bundle" --sets rep,single,layer --count 100 --walks 2000 \
  --cache "$work/evalcache" --json "$work/evaluation.json" --plots "$work/eval-plots"
stage "done"
