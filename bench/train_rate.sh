#!/usr/bin/env bash
# Training throughput of the decoder and the layering network under each OpenBLAS kernel
# family (issue 18: "decoder and layering training at >= 1.7x today's steps per second").
# One thread; rates per CPU-second (user + system) beside per wall-second, because only the
# former is stable on a machine that is running other jobs; the "loop" columns are the training
# loop alone (from the run's log, wall time), without process start and validation.
#
#   bash bench/train_rate.sh [BUILD_DIR]            (build by default)
#   CORES="keep Haswell SkylakeX" STEPS=150 EPOCHS=4 bash bench/train_rate.sh
#
# "keep" is the family OpenBLAS picks by itself (Prescott on a CPU whose name it does not
# know, Haswell on most AVX2/AVX-512 machines); the others are forced through
# NBRDF_BLAS_CORETYPE (src/cli/cli_blas.c). AVX-512 families are skipped on CPUs without it.
# Data: generated sets of 1,024 single BRDFs (a decoder step draws 16 rows of each) and
# 48 two-layer BRDFs (pairs per second count all 48, a tenth of which the trainer holds out)
# in a temporary folder; the layering network is
# trained with models/v1's decoder and tables (the bundle the published rates used), paper
# preset, decoded loss.
set -euo pipefail
cd "$(dirname "$0")/.."
B=${1:-build}
N=$B/nbrdf
CORES=${CORES:-keep Haswell SkylakeX}
STEPS=${STEPS:-1000}
EPOCHS=${EPOCHS:-300}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1

$N dataset --out "$T/single.nbds" --kind single --count 1024 --seed 7 --threads 0 2>/dev/null
$N dataset --out "$T/layered2.nbds" --kind layered2 --count 48 --seed 7 --threads 0 2>/dev/null

# cpu_wall CMD...: runs CMD, prints "CPU-seconds wall-seconds".
cpu_wall() {
  local TIMEFORMAT='%U %S %R'
  { time "$@" >/dev/null 2>"$T/err" || { cat "$T/err" >&2; exit 1; }; } 2>"$T/time"
  awk '{printf "%.2f %.2f\n", $1 + $2, $3}' "$T/time"
}

# loop_rate CSV: units per second of the training loop alone, from its log (first to last row,
# so process start, data loading and the final validation are left out; wall seconds).
loop_rate() { awk -F, 'NR == 2 {u0 = $1; t0 = $2} NR > 2 {u = $1; t = $2} END {printf "%.2f", (u - u0) / (t - t0)}' "$1"; }

printf '| kernels (NBRDF_BLAS_CORETYPE) | BLAS line | decoder steps / CPU-s | decoder steps / s | decoder loop steps / s | layering pairs / CPU-s | layering pairs / s | layering loop pairs / s |\n'
printf '|---|---|---|---|---|---|---|---|\n'
for core in $CORES; do
  if [[ $core == SkylakeX || $core == Cooperlake || $core == SapphireRapids ]] &&
     ! grep -q avx512f /proc/cpuinfo; then
    continue
  fi
  blas=$(NBRDF_BLAS_CORETYPE=$core $N --version 2>&1 | grep -o 'kernels [A-Za-z0-9]*' | head -1)
  rm -rf "$T/run"
  read -r dc dw < <(NBRDF_BLAS_CORETYPE=$core cpu_wall $N train decoder --data "$T/single.nbds" \
    --run "$T/run" --preset medium --steps "$STEPS" --validation 4 --checkpoint-minutes 60)
  rm -f "$T/l.ckpt" "$T/l.safetensors"
  read -r lc lw < <(NBRDF_BLAS_CORETYPE=$core cpu_wall $N train layering --loss decoded \
    --preset paper --decoder models/v1/decoder.safetensors \
    --tables models/v1/base_tables.safetensors --data "$T/layered2.nbds" \
    --epochs "$EPOCHS" --checkpoint "$T/l.ckpt" -o "$T/l.safetensors" --log "$T/l.csv")
  dl=$(loop_rate "$T/run/log.csv") ll=$(loop_rate "$T/l.csv")
  awk -v c="$core" -v b="$blas" -v s="$STEPS" -v e="$EPOCHS" -v dc="$dc" -v dw="$dw" \
      -v lc="$lc" -v lw="$lw" -v dl="$dl" -v ll="$ll" \
      'BEGIN {printf "| %s | %s | %.2f | %.2f | %.2f | %.1f | %.1f | %.1f |\n", c, b, s / dc, s / dw, dl, e * 48 / lc, e * 48 / lw, ll * 48}'
done
