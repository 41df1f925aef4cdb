#!/usr/bin/env bash
# 'nbrdf fit' and 'nbrdf bake --fit' on an untrained bundle: fit + bake with it give the
# texels of the one-call bake (the same inputs, level, budget and seed: the same fit, and
# the evaluate stage then runs the same networks in the same batch shapes, so bit for bit),
# the texture carries the fit's decoder and names the fit; a bake refuses (exit 1, message
# naming the fit file and what differs) a fit made with another bundle, other options or
# from another map, and a missing or damaged .nbfit; usage errors exit 2; Ctrl-C during the
# fit leaves no file. The library cases (every level, two tiles, the refusals in detail)
# are in tests/bake/test_bake_fit.c.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
export OPENBLAS_NUM_THREADS=1
"$NBRDF" bundle init bundle --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
"$NBRDF" bundle init other --seed 4 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
oiiotool --pattern fill:left=0.1:right=0.6 16x16 1 -d uint8 -o a1.png
oiiotool --pattern fill:top=0.1:bottom=0.6 16x16 1 -d uint8 -o a2.png
maps=(--alpha1 a1.png --eta 1.5 --alpha2 0.3 --r0 0.9 --albedo 0.7 --sigma-t 1)
base=(--bundle bundle "${maps[@]}")
level=(--accuracy specialised --budget 2 --seed 5)

expect_exit 0 "$NBRDF" fit "${base[@]}" "${level[@]}" --progress=json -o s.nbfit
check "fit: ground truth stage" grep -Fq '"stage":"ground truth"' "$TMP/out"
check "fit: done line" \
  grep -Eq '"event":"done","output":"s.nbfit","accuracy":"specialised","tiles":1,"budget":2,' "$TMP/out"
sum=$(grep -o '"decoder_checksum":"[0-9a-f]*"' "$TMP/out" | cut -d'"' -f4)
fitsum=$(grep -o '"fit_checksum":"[0-9a-f]*"' "$TMP/out" | cut -d'"' -f4)
check "fit: a decoder checksum" test ${#sum} = 16

expect_exit 0 "$NBRDF" bake "${base[@]}" "${level[@]}" --float -o one.exr
expect_exit 0 "$NBRDF" bake "${base[@]}" --fit s.nbfit --float -o two.exr
check "bake --fit reports the fit's level" grep -Fq "accuracy specialised (budget 2 s)" "$TMP/out"
check "bake --fit: the one-call bake's texels, every level" \
  oiiotool one.exr two.exr --fail 0 --failpercent 0 --diff
"$NBRDF" info two.exr >info.txt 2>&1
check "the texture carries the fit's decoder" grep -Fq "checksum $sum" info.txt
check "the texture names the fit" grep -Eq "^accuracy: level=specialised; .*; fit=$fitsum\$" info.txt

# A UDIM set: one fit over both tiles, both textures carry its decoder.
cp a1.png r.1001.png
cp a2.png r.1002.png
expect_exit 0 "$NBRDF" fit --bundle bundle --alpha1 'r.<UDIM>.png' --eta 1.5 --alpha2 0.3 \
  --r0 0.9 --albedo 0.7 --sigma-t 1 "${level[@]}" --progress=json -o set.nbfit
check "set: a fit over two tiles" grep -Fq '"tiles":2,' "$TMP/out"
setsum=$(grep -o '"decoder_checksum":"[0-9a-f]*"' "$TMP/out" | cut -d'"' -f4)
for t in 1001 1002; do
  expect_exit 0 "$NBRDF" bake --bundle bundle --alpha1 r.$t.png --eta 1.5 --alpha2 0.3 --r0 0.9 \
    --albedo 0.7 --sigma-t 1 --fit set.nbfit -o l.$t.exr
  "$NBRDF" info l.$t.exr >info.$t.txt 2>&1
  check "set: tile $t carries the set's decoder $setsum" grep -Fq "checksum $setsum" info.$t.txt
done
# The set baked at once with the fit: the same decoder in every tile, and a tile baked with
# another fit is not up to date.
expect_exit 0 "$NBRDF" bake --bundle bundle --alpha1 'r.<UDIM>.png' --eta 1.5 --alpha2 0.3 \
  --r0 0.9 --albedo 0.7 --sigma-t 1 --fit set.nbfit -o 'm.<UDIM>.exr'
for t in 1001 1002; do
  "$NBRDF" info m.$t.exr >minfo.$t.txt 2>&1
  check "set bake: tile $t carries the set's decoder" grep -Fq "checksum $setsum" minfo.$t.txt
done
check "set bake with a fit: no per-tile fit note" bash -c '! grep -q "fits each of the" "$0"' "$TMP/err"
expect_exit 0 "$NBRDF" bake --bundle bundle --alpha1 'r.<UDIM>.png' --eta 1.5 --alpha2 0.3 \
  --r0 0.9 --albedo 0.7 --sigma-t 1 --fit set.nbfit -o 'm.<UDIM>.exr'
check "set bake again with the same fit: up to date" grep -Fq "0 baked, 2 skipped" "$TMP/out"
cp set.nbfit set2.nbfit
"$NBRDF" fit --bundle bundle --alpha1 'r.<UDIM>.png' --eta 1.5 --alpha2 0.3 --r0 0.9 \
  --albedo 0.7 --sigma-t 1 --accuracy specialised --budget 2 --seed 6 -o set2.nbfit >/dev/null 2>&1
expect_exit 0 "$NBRDF" bake --bundle bundle --alpha1 'r.<UDIM>.png' --eta 1.5 --alpha2 0.3 \
  --r0 0.9 --albedo 0.7 --sigma-t 1 --fit set2.nbfit -o 'm.<UDIM>.exr'
check "set bake with another fit: every tile baked again" grep -Fq "2 baked, 0 skipped" "$TMP/out"

expect_exit 1 "$NBRDF" fit --bundle bundle --alpha1 'r.<UDIM>.png' --eta 1.5 --alpha2 'q.<UDIM>.png' \
  --r0 0.9 --albedo 0.7 --sigma-t 1 "${level[@]}" -o bad.nbfit
check "set: a pattern without files" grep -Fq -- "--alpha2 'q.<UDIM>.png' matches no file" "$TMP/err"

# Refusals: exit 1, the fit file and what differs named, no output.
expect_exit 1 "$NBRDF" bake --bundle other "${maps[@]}" --fit s.nbfit -o bad.exr
check "another bundle" grep -Fq "s.nbfit: fitted with the bundle of checksum" "$TMP/err"
expect_exit 1 "$NBRDF" bake "${base[@]}" --fit s.nbfit --quantise 8 -o bad.exr
check "other options" grep -Fq "s.nbfit: fitted with quantise bits off, but this bake has quantise bits 8" "$TMP/err"
expect_exit 1 "$NBRDF" bake "${base[@]}" --fit s.nbfit --accuracy fitted -o bad.exr
check "another level" grep -Fq "fitted with accuracy specialised, but this bake has accuracy fitted" "$TMP/err"
expect_exit 1 "$NBRDF" bake --bundle bundle --alpha1 a2.png --eta 1.5 --alpha2 0.3 --r0 0.9 \
  --albedo 0.7 --sigma-t 1 --fit s.nbfit -o bad.exr
check "another map" grep -Fq "s.nbfit: the alpha1 map a2.png (map fnv1a64=" "$TMP/err"
expect_exit 1 "$NBRDF" bake "${base[@]}" --fit missing.nbfit -o bad.exr
check "a missing fit" grep -Fq "missing.nbfit" "$TMP/err"
head -c 300 s.nbfit >cut.nbfit
expect_exit 1 "$NBRDF" bake "${base[@]}" --fit cut.nbfit -o bad.exr
check "a truncated fit" grep -Fq "cut.nbfit" "$TMP/err"
expect_exit 1 "$NBRDF" bake "${base[@]}" --fit bundle/decoder.safetensors -o bad.exr
check "a safetensors file that is no fit" grep -Fq "not a fit file" "$TMP/err"
expect_exit 1 "$NBRDF" bake "${base[@]}" --fit s.nbfit -o s.nbfit
check "the texture may not replace the fit" test -s s.nbfit
check "no file after refusals" test ! -e bad.exr

# Usage errors.
expect_exit 2 "$NBRDF" fit "${base[@]}" -o u.nbfit
check "fit: --accuracy required" grep -Fq -- "--accuracy fitted, specialised or compact is required" "$TMP/err"
expect_exit 2 "$NBRDF" fit "${base[@]}" --accuracy fast -o u.nbfit
check "fit: fast is no level to fit" grep -Fq -- "--accuracy expects fitted, specialised or compact" "$TMP/err"
expect_exit 2 "$NBRDF" fit "${base[@]}" --accuracy fitted --budget 0.2 -o u.nbfit
check "fit: too small a budget" grep -Fq "too small for 'fitted'" "$TMP/err"
expect_exit 2 "$NBRDF" fit "${base[@]}" --accuracy fitted
check "fit: -o required" grep -Fq -- "-o SCENE.nbfit is required" "$TMP/err"
cp a1.png a1.keep
expect_exit 1 "$NBRDF" fit "${base[@]}" --accuracy fitted --budget 2 -o a1.png
check "fit: the output may not replace a map" cmp -s a1.png a1.keep
check "no fit after usage errors" test ! -e u.nbfit

# Ctrl-C during the fit: exit 1, no file, no temporary file.
"$NBRDF" fit "${base[@]}" --accuracy specialised --budget 12 --progress=json -o c.nbfit \
  >cancel.out 2>cancel.err &
pid=$!
until grep -q '"stage":"fit"' cancel.out 2>/dev/null || ! kill -0 $pid 2>/dev/null; do sleep 0.05; done
kill -INT $pid 2>/dev/null
wait $pid
rc=$?
check "cancelled fit exits 1 (got $rc)" test "$rc" = 1
check "cancelled fit says so" grep -Fq "cancelled; no file written" cancel.err
check "cancelled fit leaves no file" bash -c '! ls -a | grep -q "c\.nbfit"'

expect_output "^usage: nbrdf fit " "$NBRDF" fit --help
expect_output "--fit FILE" "$NBRDF" bake --help
finish
