#!/usr/bin/env bash
# The paper's Table 3 (equal-time MSE of the neural and the reference mode
# against a high-sample reference image) and Fig. 5 (mip-mapping against
# aliasing at 1 spp), with nbrdf render. Writes images and table3.md /
# fig5.md into OUT.
#
#   bash bench/render_paper.sh [BUNDLE] [OUT]      (defaults: models/default, build/render_paper)
#   SIZE=128 NEURAL_SPP=16 GT_SPP=1024 FIG5_SIZE=256 NBRDF=build/nbrdf  (environment)
#   LEVELS="fast specialised compact compact:4": the bake accuracy levels of the neural images
#   (issue 19; compact:K bakes --compact K; the texture of each, its decoder's queries/s
#   inside the renderer, and its equal-time reference). FIG5=0 skips Fig. 5.
#
# The figures mean something only with a trained bundle; with an untrained one
# (nbrdf bundle init) the script runs end to end and the neural numbers are noise.
set -euo pipefail
cd "$(dirname "$0")/.."
BUNDLE=${1:-models/default}
OUT=${2:-build/render_paper}
NBRDF=${NBRDF:-build/nbrdf}
SIZE=${SIZE:-128}
NEURAL_SPP=${NEURAL_SPP:-16}
GT_SPP=${GT_SPP:-1024}
FIG5_SIZE=${FIG5_SIZE:-256}
mkdir -p "$OUT"

# A coated copper-like material with a coloured, scattering slab.
params=(--alpha1 0.05 --eta 1.5 --alpha2 0.2 --r0 0.95,0.64,0.54 --albedo 0.9,0.5,0.3 --sigma-t 2)
LEVELS=${LEVELS:-fast}
for level in $LEVELS; do
  acc=(--accuracy "$level")
  [[ $level == compact:* ]] && acc=(--accuracy compact --compact "${level#compact:}")
  "$NBRDF" bake --bundle "$BUNDLE" "${params[@]}" "${acc[@]}" -o "$OUT/material-$level.exr" \
    >"$OUT/bake-$level.txt"
done
cp "$OUT/material-${LEVELS%% *}.exr" "$OUT/material.exr"

now() { date +%s.%N; }
# mse A B: mean squared error over all pixels and channels (idiff's RMS squared).
mse() { idiff -v -fail 1e30 -warn 1e30 "$1" "$2" | awk '/RMS error/ {printf "%.4g", $4 * $4}'; }

scenes=("sphere sky 3,4,4,30" "plane sky none" "sphere white none")
{
  echo "| scene | level | neural spp | time s | decoder queries/s in the render | neural MSE | reference spp (equal time) | reference MSE |"
  echo "|---|---|---|---|---|---|---|---|"
} >"$OUT/table3.md"
for s in "${scenes[@]}"; do
  read -r scene env light <<<"$s"
  name="$scene-$env"
  common=(--scene "$scene" --env "$env" --light "$light" --width "$SIZE" --height "$SIZE")
  "$NBRDF" render "$OUT/material.exr" --mode reference "${params[@]}" "${common[@]}" \
    --spp "$GT_SPP" --seed 1000 -o "$OUT/$name-gt.exr" --png "$OUT/$name-gt.png" >/dev/null
  for level in $LEVELS; do
    sfx=$([ "$level" = "${LEVELS%% *}" ] && echo "" || echo "-$level")
    t0=$(now)
    "$NBRDF" render "$OUT/material-$level.exr" --bundle "$BUNDLE" "${common[@]}" \
      --spp "$NEURAL_SPP" --seed 1 -o "$OUT/$name-neural$sfx.exr" --png "$OUT/$name-neural$sfx.png" \
      >"$OUT/render-$name-$level.txt" 2>&1
    tn=$(awk -v a="$(now)" -v b="$t0" 'BEGIN { print a - b }')
    rate=$(sed -n 's/^decoder: \([0-9.e+]*\) queries.*/\1/p' "$OUT/render-$name-$level.txt")
    # The reference's cost per sample from a short probe, then as many samples as fit in tn.
    t0=$(now)
    "$NBRDF" render "$OUT/material.exr" --mode reference "${params[@]}" "${common[@]}" --spp 4 \
      --seed 2 -o "$OUT/probe.exr" >/dev/null
    tp=$(awk -v a="$(now)" -v b="$t0" 'BEGIN { print a - b }')
    rspp=$(awk -v n="$tn" -v p="$tp" 'BEGIN { s = int(4 * n / p); print s < 1 ? 1 : s }')
    "$NBRDF" render "$OUT/material.exr" --mode reference "${params[@]}" "${common[@]}" \
      --spp "$rspp" --seed 3 -o "$OUT/$name-reference$sfx.exr" \
      --png "$OUT/$name-reference$sfx.png" >/dev/null
    printf "| %s | %s | %d | %.2f | %s | %s | %d | %s |\n" "$name" "$level" "$NEURAL_SPP" "$tn" \
      "${rate:-—}" "$(mse "$OUT/$name-neural$sfx.exr" "$OUT/$name-gt.exr")" "$rspp" \
      "$(mse "$OUT/$name-reference$sfx.exr" "$OUT/$name-gt.exr")" >>"$OUT/table3.md"
  done
done
rm -f "$OUT/probe.exr"
[ "${FIG5:-1}" = 1 ] || exit 0

# Fig. 5: a fine checker of roughness and colour on the receding plane at 1 spp,
# level 0 only against trilinear mip filtering; the target is level 0 supersampled.
oiiotool --pattern checker:width=2:height=2:color1=0.05:color2=0.5 256x256 1 -d float \
  -o "$OUT/checker_alpha.exr"
oiiotool --pattern checker:width=2:height=2:color1=0.95,0.64,0.54:color2=0.2,0.2,0.2 256x256 3 \
  -d float -o "$OUT/checker_r0.exr"
"$NBRDF" bake --bundle "$BUNDLE" --alpha1 0.1 --eta 1.5 --alpha2 "$OUT/checker_alpha.exr" \
  --r0 "$OUT/checker_r0.exr" --albedo 0.8 --sigma-t 1 -o "$OUT/checker.exr" >/dev/null 2>&1
plane=(--bundle "$BUNDLE" --scene plane --plane-repeat 0.5 --width "$FIG5_SIZE" --height "$FIG5_SIZE")
"$NBRDF" render "$OUT/checker.exr" "${plane[@]}" --spp 1 --no-mip -o "$OUT/fig5-nomip.exr" \
  --png "$OUT/fig5-nomip.png" >/dev/null 2>&1
"$NBRDF" render "$OUT/checker.exr" "${plane[@]}" --spp 1 -o "$OUT/fig5-mip.exr" \
  --png "$OUT/fig5-mip.png" >/dev/null 2>&1
"$NBRDF" render "$OUT/checker.exr" "${plane[@]}" --spp 64 --no-mip -o "$OUT/fig5-target.exr" \
  --png "$OUT/fig5-target.png" >/dev/null 2>&1
{
  echo "| 1 spp | MSE against level 0 at 64 spp |"
  echo "|---|---|"
  echo "| level 0 only | $(mse "$OUT/fig5-nomip.exr" "$OUT/fig5-target.exr") |"
  echo "| trilinear mip | $(mse "$OUT/fig5-mip.exr" "$OUT/fig5-target.exr") |"
} >"$OUT/fig5.md"
cat "$OUT/table3.md" "$OUT/fig5.md"
