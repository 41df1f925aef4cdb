#!/usr/bin/env bash
# 'nbrdf bake's range report: before any network work, every parameter outside the model's
# trained range is reported at once, in the units typed (perceptual roughness, IOR), with the
# value it is baked as and a texel count (exact for the map made here; a constant counts
# once); with --progress=json also one "range" event each, before the first progress line;
# --range refuse reports the same, then exits 1 naming the file and first texel.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
"$NBRDF" bundle init bundle --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
# 16x16 perceptual roughness 0.5, with a 4x2 block (8 texels) at 0.05 from (6, 3): alpha
# 0.0025, below the trained 0.01 (r 0.1).
oiiotool --pattern constant:color=0.5 16x16 1 --fill:color=0.05 4x2+6+3 -d float -o alpha1.exr

args=(--bundle bundle --roughness perceptual --alpha1 alpha1.exr --eta 3 --alpha2 0.5
  --r0 0.9,0.6,0.5 --albedo 0.7 --sigma-t 7,1,9 --mip-levels 1 --energy-audit 0)

expect_exit 0 "$NBRDF" bake "${args[@]}" -o out.exr
check "alpha1 counted in perceptual roughness: $(cat "$TMP/err")" grep -Fxq \
  "nbrdf bake: alpha1 (perceptual roughness): 8 texels below 0.1 (min 0.05) will be baked as 0.1" \
  "$TMP/err"
check "eta in IOR, a constant once" grep -Fxq \
  "nbrdf bake: eta (IOR): 3 is above 2 and will be baked as 2" "$TMP/err"
check "an RGB constant once, its highest channel" grep -Fxq \
  "nbrdf bake: sigma_t (optical depth): 9 is above 5 and will be baked as 5" "$TMP/err"
check "no other range line" test "$(grep -Ec '^nbrdf bake: [a-z0-9_]+ \([A-Za-z ]+\): ' "$TMP/err")" = 3

expect_exit 0 "$NBRDF" bake "${args[@]}" --progress=json -o out.exr
check "json range event: $(head -1 "$TMP/out")" grep -Fxq \
  '{"event":"range","parameter":"alpha1","units":"perceptual roughness","constant":false,"below":8,"above":0,"min":0.05,"lo":0.1,"hi":1,"policy":"clamp","message":"alpha1 (perceptual roughness): 8 texels below 0.1 (min 0.05) will be baked as 0.1"}' \
  "$TMP/out"
check "json: three range events before the first progress line" test \
  "$(grep -m1 -n '"event":"progress"' "$TMP/out" | cut -d: -f1)" = 4
check "json: eta's event" grep -Fq \
  '{"event":"range","parameter":"eta","units":"IOR","constant":true,"below":0,"above":1,"max":3,"lo":' \
  "$TMP/out"

expect_exit 1 "$NBRDF" bake "${args[@]}" --range refuse --progress=json -o refused.exr
check "refuse: all three reported" test "$(grep -c '"event":"range"' "$TMP/out")" = 3
check "refuse: no progress" test "$(grep -c '"event":"progress"' "$TMP/out")" = 0
# The first refused value in the bake's order (rows, texels, channels, parameters): eta's
# constant at the first texel; with eta inside, the map's first texel outside.
check "refuse: names the first refused value: $(tail -1 "$TMP/err")" grep -Fq \
  "eta (constant) = 3 is outside the model's trained range" "$TMP/err"
check "refuse: the report says the range" grep -Fq \
  "nbrdf bake: eta (IOR): 3 is above 2 (trained range [" "$TMP/err"
expect_exit 1 "$NBRDF" bake "${args[@]}" --eta 1.5 --sigma-t 1 --range refuse -o refused.exr
check "refuse: names the file and first texel: $(tail -1 "$TMP/err")" grep -Fq \
  "alpha1.exr: texel (6, 3), alpha1 = 0.05 (perceptual roughness r" "$TMP/err"
check "refuse: no output" test ! -e refused.exr
finish
