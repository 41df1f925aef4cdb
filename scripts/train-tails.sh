#!/usr/bin/env bash
# Fine-tunes a bundle for the tails of the universal path (issue 35 part 3): low-IOR coats
# (eta <= 1.2) and sharp coats (alpha1 <= 0.05). The decoder is kept, so the new bundle
# reads every texture the old one baked (--reads-textures-of); what changes is what a bake
# feeds it:
#   - base tables re-projected with the eta nodes dense at the dim end (eta-warp 2, 12 nodes:
#     the dielectric's reflectance changes fastest just above eta = 1);
#   - the layering network fine-tuned from the old one, through the frozen decoder, on
#     two-layer BRDFs of the `tails` draws mixed with Table 2's two- and three-layer ones
#     (the replay keeps the Table-2 figures), with the energy penalty on.
# The sampler is the old bundle's (it maps latents of the same decoder).
# Every stage resumes (run the script again after an interruption); deterministic by seed.
#
#   bash scripts/train-tails.sh [WORK_DIR] [BUNDLE_DIR]
#   (defaults: data/tails and models/tails; BASE=models/default the bundle fine-tuned;
#    NBRDF=path/to/nbrdf; TABLES warp (or base: the base bundle's tables); TAILS_COUNT 3000, REPLAY2 1500, REPLAY3 150, EPOCHS 60,
#    EVAL_WALKS 500; NBRDF_EVALUATE=0 stops before the evaluation)
# docs/TRAINING.md, "Tails fine-tune", has the figures of a run.
set -euo pipefail
cd "$(dirname "$0")/.."
work=${1:-data/tails}
bundle=${2:-models/tails}
base=${BASE:-models/default}
nbrdf=${NBRDF:-build/nbrdf}
[ -x "$nbrdf" ] || bash scripts/build.sh build >/dev/null
export OPENBLAS_NUM_THREADS=1
mkdir -p "$work"
stage() { echo "== $(date -u +%H:%M:%S) $*"; }

# 1. Data: the tails draws (seed 5, a training family) and a replay of the default's data
#    (seed 1 and 3: the first records of the files models/default trained on).
stage "data: ${TAILS_COUNT:-3000} tails two-layer BRDFs, ${REPLAY2:-1500} + ${REPLAY3:-150} replayed"
"$nbrdf" dataset --out "$work/layered2-tails.nbds" --kind layered2 --count "${TAILS_COUNT:-3000}" \
  --seed 5 --draws tails
"$nbrdf" dataset --out "$work/layered2-table2.nbds" --kind layered2 --count "${REPLAY2:-1500}" \
  --seed 1 --draws table2
"$nbrdf" dataset --out "$work/layered3-table2.nbds" --kind layered3 --count "${REPLAY3:-150}" \
  --seed 3 --draws table2
data="$work/layered2-tails.nbds,$work/layered2-table2.nbds,$work/layered3-table2.nbds"

# 2. Base tables with the base bundle's decoder, eta nodes 1 + u^2 (12 of them); TABLES=base
#    keeps the base bundle's.
if [ "${TABLES:-warp}" = base ]; then
  cp "$base/base_tables.safetensors" "$work/base_tables.safetensors"
elif [ ! -f "$work/base_tables.safetensors" ]; then
  stage "base tables, eta warped (resumable)"
  "$nbrdf" train tables --decoder "$base/decoder.safetensors" -o "$work/base_tables.safetensors" \
    --checkpoint "$work/base_tables.ckpt" --eta-min 1 --eta-warp 2 --eta-nodes 12
fi

# 3. Layering network: from the base bundle's, decoded loss through its frozen decoder.
if [ ! -f "$work/layering.safetensors" ]; then
  stage "layering network, tails fine-tune (resumable)"
  "$nbrdf" train layering --loss decoded --preset paper --decoder "$base/decoder.safetensors" \
    --tables "$work/base_tables.safetensors" --init "$base/layering.safetensors" \
    --data "$data" --epochs "${EPOCHS:-60}" --lr 2.5e-4 --decay-every 20 --energy 0.1 \
    --checkpoint "$work/layering.ckpt" -o "$work/layering.safetensors" --log "$work/layering.csv"
fi

# 4. The bundle: the base's decoder and sampler, so it reads the base's textures.
stage "bundle -> $bundle"
"$nbrdf" train bundle -o "$bundle" --name "$(basename "$bundle")" --decoder "$base/decoder.safetensors" \
  --tables "$work/base_tables.safetensors" --layering "$work/layering.safetensors" \
  --sampler "$base/sampler.safetensors" --reads-textures-of "$base" \
  --note "scripts/train-tails.sh: $base fine-tuned for low-IOR and sharp coats (tables eta-warp 2, 12 eta nodes; layering ${EPOCHS:-60} epochs on tails + replay, energy 0.1)"

[ "${NBRDF_EVALUATE:-1}" = 1 ] || { stage "done (NBRDF_EVALUATE=0: not evaluated)"; exit 0; }
stage "evaluation: tails, layer, layer3, table"
#    (tails: 99 BRDFs, a third per region; the others 100, as the model cards)
"$nbrdf" evaluate --bundle "$bundle" --sets tails --count 99 --walks "${EVAL_WALKS:-500}" \
  --cache "$work/../evalcache" --json "$work/evaluation-tails.json"
"$nbrdf" evaluate --bundle "$bundle" --sets layer,layer3,table --count 100 \
  --walks "${EVAL_WALKS:-500}" --cache "$work/../evalcache" --json "$work/evaluation.json"
stage "done"
