#!/usr/bin/env bash
# Re-measures the figures the documents quote for a bundle, one stage per command, so a
# new models/default can be measured in one go (issue 18: the model card, TRAINING.md,
# SAMPLING_AND_COST.md, RENDER.md Table 3, BAKE.md). A stage whose output exists is
# skipped: run the script again after an interruption and it goes on. Outputs are the raw
# tables, JSON and images the documents cite; each stage's log is OUT/STAGE.log.
#
#   bash scripts/measure-bundle.sh [BUNDLE] [OUT]     (models/default, build/measure)
#   STAGES="evaluate sampling neural_vs_mc render bake bake_half quantise ladder" (all)
#   COUNT (held-out BRDFs per set, 100), WALKS (reference walks, 2000; the references are
#   cached in CACHE, data/evalcache, and cost about 2.5 hours at 2,000 walks on 2 cores),
#   BUILD (build).
# (The benches print their tables on stdout as well as to --out, so --out is /dev/null.)
# One OpenBLAS thread throughout: the figures are per CPU-second (docs/ARCHITECTURE.md).
set -euo pipefail
cd "$(dirname "$0")/.."
bundle=${1:-models/default}
out=${2:-build/measure}
build=${BUILD:-build}
count=${COUNT:-100}
walks=${WALKS:-2000}
cache=${CACHE:-data/evalcache}
stages=${STAGES-evaluate sampling neural_vs_mc render bake bake_half quantise ladder}
nbrdf=$build/nbrdf
[ -x "$nbrdf" ] || bash scripts/build.sh "$build" >/dev/null
export OPENBLAS_NUM_THREADS=1 OMP_WAIT_POLICY=passive
# The benches link OpenBLAS directly and keep the kernels it picks, which on some AVX-512 CPUs
# are narrower than the ones the CLI re-executes itself with (README, "Speed"): measure
# everything with the CLI's.
core=$("$nbrdf" --version | sed -n 's/.*chosen by nbrdf: OPENBLAS_CORETYPE=\([A-Za-z0-9]*\).*/\1/p')
[ -z "$core" ] || export OPENBLAS_CORETYPE=$core
mkdir -p "$out" "$cache"
"$nbrdf" bundle info "$bundle" >"$out/bundle-info.txt"

# stage NAME OUTPUT CMD...: runs CMD (its stdout into OUTPUT) unless OUTPUT exists; the
# output appears only when the command succeeded, so an interrupted stage runs again.
stage() {
  local name=$1 output=$2
  shift 2
  case " $stages " in *" $name "*) ;; *) return 0 ;; esac
  if [ -e "$output" ]; then
    echo "== $name: $output exists, skipped"
    return 0
  fi
  echo "== $(date -u +%H:%M:%S) $name -> $output"
  "$@" >"$output.part" 2>"$out/$name.log" || { echo "$name failed: $out/$name.log" >&2; exit 1; }
  mv "$output.part" "$output"
}

# Model card, TRAINING.md: held-out lobe error, point-wise and grazing figures, albedo.
stage evaluate "$out/evaluation.txt" "$nbrdf" evaluate --bundle "$bundle" \
  --sets rep,single,layer,layer3,table --count "$count" --walks "$walks" --cache "$cache" \
  --json "$out/evaluation.json" --plots "$out/eval-plots"
# SAMPLING_AND_COST.md: sampling variance under sky and furnace, white-furnace integrals.
stage sampling "$out/sampling.md" "$build/bench/bench_sampling" --bundle "$bundle" --env both \
  --out /dev/null --plot "$out/sampling"
# SAMPLING_AND_COST.md: neural path against Monte Carlo at equal error (uses evaluate's
# `layer` references).
stage neural_vs_mc "$out/neural_vs_mc.md" "$build/bench/bench_neural_vs_mc" --bundle "$bundle" \
  --cache "$cache" --ref-count "$count" --ref-walks "$walks" --out /dev/null \
  --plot "$out/neural_vs_mc.png"
# RENDER.md: Table 3 (equal-time MSE) and Fig. 5 (mip-mapping).
render() {
  SIZE=96 GT_SPP=512 FIG5=0 LEVELS="fast specialised compact" NBRDF=$nbrdf \
    bash bench/render_paper.sh "$bundle" "$out/render" >&2
  SIZE=32 GT_SPP=16 LEVELS=fast NBRDF=$nbrdf bash bench/render_paper.sh "$bundle" "$out/fig5" >&2
  cat "$out/render/table3.md" "$out/fig5/fig5.md"
}
stage render "$out/render.md" render
# BAKE.md: bake time and memory at 2048^2, half floats, quantisation.
mkdir -p "$out/bake-tmp"
stage bake "$out/bake.md" "$build/bench/bench_bake" --bundle "$bundle" --sizes 2048 --big 0 \
  --no-compression --dir "$out/bake-tmp"
case " $stages " in *" bake_half "*) [ -d "$out/maps" ] || bash examples/make_maps.sh "$out/maps" >/dev/null ;; esac
stage bake_half "$out/bake_half.md" "$build/bench/bench_bake_half" --maps "$out/maps" \
  --bundle "$bundle" --texels 64
stage quantise "$out/quantise.md" "$build/bench/bench_bake_quantise" --bundle "$bundle" \
  --size 512 --texels 32
# BAKE.md: the accuracy ladder's trade on held-out constants and on the example maps.
ladder() {
  NBRDF_BUNDLE=$bundle MAPS=0 SPP=1024 TEXELS=1 LEVELS="fast fitted specialised" \
    bash bench/ladder_trade.sh "$build" "$out/ladder-constants"
  NBRDF_BUNDLE=$bundle CONSTANTS="" TEXELS=16 LEVELS="fast fitted specialised" \
    bash bench/ladder_trade.sh "$build" "$out/ladder-maps"
}
stage ladder "$out/ladder.md" ladder
echo "== done: $out"
