#!/usr/bin/env bash
# nbrdf bake --device (issue 34, docs/GPU.md) with the trained models/default on 8x8 RGB maps:
# - --device gpu on lavapipe (NBRDF_VK_DEVICE=llvmpipe) gives the latents of --device cpu
#   within float rounding (float storage, absolute 1e-4 on every channel of level 0), and
#   the energy audit (8 tuples, decoded on the GPU) the same maximum albedo within 1e-3;
# - without a Vulkan loader (NBRDF_VULKAN_LIBRARY pointing nowhere) --device auto bakes on
#   the CPU with a one-line note, and --device gpu fails (exit 1) saying why, writing nothing.
# lavapipe runs the paper-size layering network at ~200 rows/s: the maps stay small.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
oiiotool --pattern fill:left=0.1:right=0.6 8x8 1 -d float -o alpha1.exr
oiiotool --pattern fill:top=0.9,0.3,0.5:bottom=0.2,0.8,0.4 8x8 3 -d float -o r0.exr
oiiotool --pattern fill:topleft=0.1:topright=0.9:bottomleft=0.5:bottomright=0.3 8x8 1 -d float \
  -o sigma.exr
base=(--bundle "$NBRDF_SOURCE_DIR/models/default" --alpha1 alpha1.exr --eta 1.5 --alpha2 0.3
  --r0 r0.exr --albedo 0.7 --sigma-t sigma.exr --float --energy-audit 8)

expect_exit 0 "$NBRDF" bake "${base[@]}" --device cpu -o cpu.exr
check "cpu: no note" bash -c "! grep -q note: '$TMP/err'"
cp "$TMP/out" cpu.txt

if gpu_msg=$(NBRDF_VK_DEVICE=llvmpipe "$NBRDF" bake "${base[@]}" --device gpu -o gpu.exr \
  2>&1 >gpu.txt); then
  check "gpu: the note names lavapipe" grep -q "note: networks on the GPU: llvmpipe" <<<"$gpu_msg"
  check "gpu vs cpu latents within 1e-4" oiiotool cpu.exr gpu.exr --fail 1e-4 --diff
  a=$(sed -n 's/^energy audit: max decoded directional albedo \([0-9.]*\).*/\1/p' cpu.txt)
  b=$(sed -n 's/^energy audit: max decoded directional albedo \([0-9.]*\).*/\1/p' gpu.txt)
  check "audit on the GPU: $a vs $b" awk -v a="$a" -v b="$b" \
    'BEGIN { d = a - b; exit !(a > 0 && d < 1e-3 && d > -1e-3) }'
  expect_exit 0 env NBRDF_VK_DEVICE=llvmpipe NBRDF_DEVICE=gpu "$NBRDF" bake "${base[@]}" \
    --progress=json -o env.exr
  check "NBRDF_DEVICE=gpu: json names the device" grep -q '"device":"llvmpipe' "$TMP/out"
  # eval --texture: the decoder on the GPU gives the CPU's values.
  { echo "u,v,theta_i,phi_i,theta_o,phi_o"
    for k in 0 1 2 3 4 5 6 7 8 9; do echo "0.$k,0.${k}5,$((k * 8)),$((k * 30)),$((k * 7 + 3)),$((k * 35))"; done
  } >q.csv
  expect_exit 0 "$NBRDF" eval --texture cpu.exr --in q.csv --device cpu
  cp "$TMP/out" eval_cpu.csv
  expect_exit 0 env NBRDF_VK_DEVICE=llvmpipe "$NBRDF" eval --texture cpu.exr --in q.csv --device gpu
  cp "$TMP/out" eval_gpu.csv
  check "eval --texture: the note" grep -q "nbrdf eval: note: networks on the GPU" "$TMP/err"
  check "eval --texture on the GPU: f within 1e-5 relative" awk -F, '
    NR == FNR { if (FNR > 1) for (c = 7; c <= 9; c++) a[FNR, c] = $c; next }
    FNR > 1 { for (c = 7; c <= 9; c++) { d = $c - a[FNR, c]; if (d < 0) d = -d
                m = a[FNR, c] < 0 ? -a[FNR, c] : a[FNR, c]; if (d > 1e-5 * (m > 1e-3 ? m : 1e-3)) bad++ }
              rows++ }
    END { exit !(rows == 10 && !bad) }' eval_cpu.csv eval_gpu.csv
elif grep -q "built without GPU support\|no Vulkan" <<<"$gpu_msg"; then
  echo "skipped the lavapipe comparison: $gpu_msg"
else
  check "gpu bake on lavapipe: $gpu_msg" false
fi

# No Vulkan loader at all.
nowhere=(env NBRDF_VULKAN_LIBRARY="$TMP/no/libvulkan.so.1")
expect_exit 0 "${nowhere[@]}" "$NBRDF" bake "${base[@]}" --energy-audit 0 --device auto -o auto.exr
check "auto: one note line" test "$(grep -c "note:" "$TMP/err")" = 1
check "auto: the note says CPU" grep -q "note: no GPU for the networks (.*): they run on the CPU" \
  "$TMP/err"
check "auto: a texture" test -s auto.exr
expect_exit 1 "${nowhere[@]}" "$NBRDF" bake "${base[@]}" --device gpu -o none.exr
check "gpu without Vulkan: the message says why" grep -Eq "device gpu: .*(no Vulkan|without GPU)" \
  "$TMP/err"
check "gpu without Vulkan: no file" test ! -e none.exr
expect_exit 2 "$NBRDF" bake "${base[@]}" --device tpu -o bad.exr
expect_exit 2 env NBRDF_DEVICE=fast "$NBRDF" bake "${base[@]}" -o bad.exr
expect_exit 2 "$NBRDF" eval --model layered --device gpu --in /dev/null
finish
