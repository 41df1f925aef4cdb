#!/usr/bin/env bash
# 'nbrdf bake --compact K[,WIDTH]' (issue 19) on an untrained bundle: bad
# values are refused with a message and leave no file; --compact implies
# --accuracy compact and clashes with another level; a compact bake reports
# its channels and decoder (JSON done line, "distil" progress stage); 'nbrdf
# info' shows K latent channels and the compact decoder; 'eval --texture'
# decodes it; 'verify' measures its energy with the texture's own decoder (the
# same maximum albedo as the bake's audit in the header); 'render' reports the
# decoder's rate. The library cases are in tests/bake/test_bake_compact.c.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
export OPENBLAS_NUM_THREADS=1
"$NBRDF" bundle init bundle --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
base=(--bundle bundle --alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9 --albedo 0.7 --sigma-t 1)

for v in 0 9 x 8,2 8,300 8, 8,32,1 ,32; do
  expect_exit 2 "$NBRDF" bake "${base[@]}" --compact "$v" -o bad.exr
  check "--compact $v message" grep -Fq -- "--compact expects K[,WIDTH]" "$TMP/err"
done
expect_exit 2 "$NBRDF" bake "${base[@]}" --accuracy fitted --compact 8 -o bad.exr
check "--compact with another level" grep -Fq -- "--compact goes with --accuracy compact" "$TMP/err"
expect_exit 2 "$NBRDF" bake "${base[@]}" --compact 8 --accuracy specialised -o bad.exr
check "another level after --compact" grep -Fq -- "--compact goes with --accuracy compact" \
  "$TMP/err"
expect_exit 2 "$NBRDF" bake "${base[@]}" --compact 8 --budget 0.5 -o bad.exr
check "too small a budget says what fits" grep -Fq "too small for 'compact'" "$TMP/err"
check "no file after refusals" test ! -e bad.exr

expect_exit 0 "$NBRDF" bake "${base[@]}" --compact 6,16 --budget 4 --progress=json -o c.exr
check "distil stage" grep -Fq '"stage":"distil"' "$TMP/out"
check "done line reports the compact texture" \
  grep -Eq '"accuracy":"compact",.*"compact":6,"decoder_macs":[0-9]+,"variance_kept":' "$TMP/out"
"$NBRDF" info c.exr >info.txt 2>&1
check "info: 6 latent channels" grep -Fq "latent dim 6 per colour channel" info.txt
check "info: the compact decoder" grep -Fq "own decoder: compact, log1p output" info.txt
check "info: the accuracy attribute" grep -Eq '^accuracy: level=compact; .*compact=6; compactWidth=16;' info.txt

printf 'u,v,theta_i,phi_i,theta_o,phi_o\n0.5,0.5,30,0,30,180\n0.5,0.5,60,0,20,90\n' >q.csv
expect_exit 0 "$NBRDF" eval --texture c.exr --bundle bundle --in q.csv
check "eval --texture decodes two queries" \
  bash -c "[ \$(grep -cE '^0.5,0.5,[0-9]+,0,[0-9]+,[0-9]+,[0-9.e+-]+$' '$TMP/out') = 2 ]"

expect_exit 0 "$NBRDF" verify c.exr "${base[@]}" --spp 16 --json v.json
header=$(sed -n 's/^max albedo: *\([0-9.]*\).*/\1/p' info.txt)
measured=$(python3 -c 'import json,sys; print(json.load(open("v.json"))["max_albedo"])')
check "verify's max albedo ($measured) is the bake audit's ($header)" python3 -c "
import sys; a, b = float('$measured'), float('$header'); sys.exit(abs(a - b) > 2e-3 * max(1, b))"

expect_exit 0 "$NBRDF" render c.exr --bundle bundle --width 16 --height 16 --spp 2 -o r.exr
check "render reports the decoder's rate" grep -Eq '^decoder: [0-9.e+]+ queries/s inside the renderer' \
  "$TMP/out"
finish
