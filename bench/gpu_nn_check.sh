#!/usr/bin/env bash
# The GPU backend's checks on a GPU machine (docs/GPU.md), one short script for the lead's
# device time. Run from a folder holding build/ (or the carried binaries at the same paths)
# and models/default; Debian's libvulkan1 unpacked and VK_DRIVER_FILES set beforehand
# (../shared/ECOSYSTEM-NOTES.md, "Vulkan on the NVIDIA GPU machine").
#
#   bash bench/gpu_nn_check.sh [BUILD_DIR] [OUT_DIR]
#
# 1. tests/gpu_test_gpu_nn on the GPU: every network preset, fp32 (limit 1e-5) and the fp16
#    tensor-core path (limit 2e-2) against the CPU;
# 2. bench/bench_gpu_nn: layering, decoder, sampler over 1 M rows, fp32 and fp16, vs the CPU;
# 3. where bench_bake was carried: a 2048^2 all-distinct RGB bake with --device gpu.
# Each step has its own time limit (90 + 200 + 200 s at most, under a 10-minute command); every output goes to OUT_DIR (default: $OUT or .).
set -u
build=${1:-build}
out=${2:-${OUT:-.}}
export NBRDF_VK_DEVICE=${NBRDF_VK_DEVICE:-NVIDIA}
export NBRDF_SOURCE_DIR=${NBRDF_SOURCE_DIR:-$PWD}
mkdir -p "$out"
{ nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null
  date -u; } | tee "$out/gpu_nn_machine.txt"
echo "== test_gpu_nn"
timeout 90 "$build/tests/gpu_test_gpu_nn" 2>&1 | tee "$out/gpu_nn_test.txt"
echo "== bench_gpu_nn"
timeout 200 "$build/bench/bench_gpu_nn" --rows 1048576 --sample 4096 --reps 3 2>&1 |
  tee "$out/gpu_nn_bench.md"
if [ -x "$build/bench/bench_bake" ]; then
  echo "== bench_bake --device gpu (2048^2)"
  timeout 200 "$build/bench/bench_bake" --sizes 2048 --big 0 --no-compression --no-layering \
    --device gpu 2>&1 | tee "$out/gpu_nn_bake.md"
fi
