#!/usr/bin/env bash
# 'nbrdf bake's range report: before any network work, every parameter outside the model's
# trained range is reported at once, in the units typed (perceptual roughness, IOR), with the
# value it is baked as and a texel count (exact for the map made here; a constant counts
# once); with --progress=json also one "range" event each, before the first progress line;
# --range refuse reports the same, then exits 1 naming the file and first texel. The fitting
# levels (fitted, specialised, compact, auto) take alpha down to 0.001 as given: per level
# words.
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
  "nbrdf bake: alpha1 (perceptual roughness): 8 texels below 0.1 (min 0.05) will be baked as 0.1 (fitted, specialised and compact fit down to 0.0316 as given)" \
  "$TMP/err"
check "eta in IOR, a constant once" grep -Fxq \
  "nbrdf bake: eta (IOR): 3 is above 2 and will be baked as 2" "$TMP/err"
check "an RGB constant once, its highest channel" grep -Fxq \
  "nbrdf bake: sigma_t (optical depth): 9 is above 5 and will be baked as 5" "$TMP/err"
check "no other range line" test "$(grep -Ec '^nbrdf bake: [a-z0-9_]+ \([A-Za-z ]+\): ' "$TMP/err")" = 3

expect_exit 0 "$NBRDF" bake "${args[@]}" --progress=json -o out.exr
check "json range event: $(head -1 "$TMP/out")" grep -Fxq \
  '{"event":"range","parameter":"alpha1","units":"perceptual roughness","constant":false,"below":8,"above":0,"min":0.05,"lo":0.1,"hi":1,"fit_lo":0.03162278,"below_fit":0,"accuracy":"fast","policy":"clamp","message":"alpha1 (perceptual roughness): 8 texels below 0.1 (min 0.05) will be baked as 0.1 (fitted, specialised and compact fit down to 0.0316 as given)"}' \
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

# The levels that fit their own ground truth take alpha down to 0.001 (r 0.0316) as given:
# the report says what each level does. eta 3 is refused after the report, before any work.
expect_exit 1 "$NBRDF" bake "${args[@]}" --range refuse --accuracy fitted --budget 60 -o refused.exr
check "fitted: what each level does: $(grep alpha1 "$TMP/err")" grep -Fxq \
  "nbrdf bake: alpha1 (perceptual roughness): 8 texels below 0.1 (min 0.05): fast bakes them as 0.1; fitted, specialised and compact fit them as given" \
  "$TMP/err"
check "fitted: eta still refused" grep -Fq "eta (constant) = 3 is outside" "$TMP/err"
expect_exit 1 "$NBRDF" bake "${args[@]}" --range refuse --accuracy auto --max-error 5 -o refused.exr
check "auto: the same words" grep -Fq \
  "8 texels below 0.1 (min 0.05): fast bakes them as 0.1; fitted, specialised and compact fit them as given" \
  "$TMP/err"
expect_exit 1 "$NBRDF" bake "${args[@]}" --alpha1 0.05 --range refuse --accuracy specialised \
  --progress=json -o refused.exr
check "specialised, a constant: $(grep alpha1 "$TMP/err")" grep -Fxq \
  "nbrdf bake: alpha1 (perceptual roughness): 0.05 is below 0.1: fast bakes it as 0.1; fitted, specialised and compact fit it as given" \
  "$TMP/err"
check "json: fit_lo and the level" grep -Fq \
  '"lo":0.1,"hi":1,"fit_lo":0.03162278,"below_fit":0,"accuracy":"specialised","policy":"refuse"' \
  "$TMP/out"
# Below even 0.001 (r 0.02: alpha 0.0004): refused under refuse, named as such.
expect_exit 1 "$NBRDF" bake "${args[@]}" --alpha1 0.02 --eta 1.5 --sigma-t 1 --range refuse \
  --accuracy specialised -o refused.exr
check "below the fitting levels' floor: $(grep alpha1 "$TMP/err" | head -1)" grep -Fxq \
  "nbrdf bake: alpha1 (perceptual roughness): 0.02 is below 0.0316, the lowest fitted, specialised and compact take (trained range [0.1, 1])" \
  "$TMP/err"
check "refused naming the constant" grep -Fq "alpha1 (constant) = 0.02 (perceptual roughness r" "$TMP/err"
expect_exit 0 "$NBRDF" bake "${args[@]}" --alpha1 0.02 --eta 1.5 --sigma-t 1 --accuracy fitted \
  --budget 4 -o floor.exr
check "clamp: fitted as the floor: $(grep alpha1 "$TMP/err" | head -1)" grep -Fxq \
  "nbrdf bake: alpha1 (perceptual roughness): 0.02 is below 0.0316, the lowest fitted, specialised and compact take: they fit it as 0.0316 (fast bakes it as 0.1)" \
  "$TMP/err"
# verify compares with the truth of the values as given and says when the texture clamped them.
expect_exit 0 "$NBRDF" bake "${args[@]}" --alpha1 0.05 --eta 1.5 --sigma-t 1 -o sharp.exr
expect_exit 0 "$NBRDF" verify sharp.exr --bundle bundle --roughness perceptual --alpha1 0.05 \
  --eta 1.5 --alpha2 0.5 --r0 0.9,0.6,0.5 --albedo 0.7 --sigma-t 1 --spp 16 --json verify.json
check "verify: the fast texture clamped alpha: $(grep note "$TMP/out")" grep -Fq \
  "note: 3 look-up(s) have alpha1 or alpha2 below the model's trained range (alpha 0.01); the ground truth is of the values as given, while this fast texture was baked with them clamped" \
  "$TMP/out"
check "verify json: texture_clamps_alpha" python3 -c '
import json, sys
v = json.load(open("verify.json"))
sys.exit(0 if v["texture_clamps_alpha"] is True and v["below_trained_alpha"] == 3 else 1)'
finish
