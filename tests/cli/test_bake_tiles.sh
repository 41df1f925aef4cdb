#!/usr/bin/env bash
# 'nbrdf bake' of a UDIM tile set (docs/FARM.md, "Tile sets") on an untrained bundle and
# 16x16 tiles made with oiiotool: one texture per tile, equal to baking that tile alone;
# maps that disagree; --tiles; resume (skip, --force, changed inputs or options); the
# progress lines; Ctrl-C in the middle of a set; 'nbrdf info' and 'nbrdf verify' of a set.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
export NBRDF_DEVICE=${NBRDF_DEVICE:-cpu} # no Vulkan probe per process: the networks run on the CPU either way here
"$NBRDF" bundle init bundle --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
tiles="1001 1002 1011 1012"
mkdir maps gap set sub bad # outputs go into folders that exist, as any bake's
for t in $tiles; do
  k=$((t % 10))
  oiiotool --pattern fill:left=0.1:right=0.$((k + 3)) 16x16 1 -d uint8 -o maps/rough.$t.png
  oiiotool --pattern fill:top=0.$((k + 1)):bottom=0.9 16x16 1 -d uint8 -o maps/depth.$t.png
  [ "$t" = 1012 ] || cp maps/depth.$t.png gap/depth.$t.png # gap/ lacks tile 1012
done
oiiotool --pattern checker:width=4:height=4:color1=0.9,0.6,0.5:color2=0.9,0.9,0.9 16x16 3 \
  -d uint8 -o r0.png # a plain file: every tile's r0

set_args=(--bundle bundle --alpha1 'maps/rough.<UDIM>.png' --eta 1.5 --alpha2 0.3 --r0 r0.png
  --albedo 0.7 --sigma-t 'maps/depth.<UDIM>.png')
# tile_args T: the same inputs for tile T alone.
tile_args() {
  echo --bundle bundle --alpha1 maps/rough.$1.png --eta 1.5 --alpha2 0.3 --r0 r0.png \
    --albedo 0.7 --sigma-t maps/depth.$1.png
}
# same_texture A B: every mip level's texels identical (idiff -a, no tolerance) and every
# header attribute the same but nbrdf:inputs, which only a set's tiles carry. The bytes of
# the texels are equal because each tile goes through the same code on the same machine in
# the same shapes (a 16x16 tile baked alone or in a set).
same_texture() {
  idiff -a -fail 0 -failpercent 0 -warn 0 "$1" "$2" >/dev/null &&
    diff <(exrheader "$1" | grep -v -e '^file ' -e 'nbrdf:inputs') \
      <(exrheader "$2" | grep -v -e '^file ' -e 'nbrdf:inputs') >/dev/null
}

# 1. The set: one texture per tile, each equal to the tile baked alone.
expect_exit 0 "$NBRDF" bake "${set_args[@]}" --progress=json -o 'set/lat.<UDIM>.exr'
check "progress names the tile" \
  grep -Eq '^\{"event":"progress","stage":"bake","done":16,"total":16,"tile":1011,"tile_index":3,"tiles":4\}$' "$TMP/out"
check "a tile event per tile" test "$(grep -c '"event":"tile".*"status":"baked"' "$TMP/out")" = 4
check "the set's done event" \
  grep -Eq '^\{"event":"done","output":"set/lat.<UDIM>.exr","tiles":4,"baked":4,"skipped":0,' "$TMP/out"
check "no file but the four tiles" test "$(ls set | tr '\n' ' ')" = \
  "lat.1001.exr lat.1002.exr lat.1011.exr lat.1012.exr "
for t in $tiles; do
  expect_exit 0 "$NBRDF" bake $(tile_args $t) -o alone.$t.exr
  check "tile $t equals the tile baked alone" same_texture alone.$t.exr set/lat.$t.exr
  check "tile $t records its inputs" sh -c "exrheader set/lat.$t.exr | grep -q 'nbrdf:inputs.*fnv1a64:'"
done
check "a single bake records no fingerprint" sh -c '! exrheader alone.1001.exr | grep -q nbrdf:inputs'

# 2. Resume: finished tiles are skipped, byte for byte untouched; a changed map re-bakes
# its tile only, a changed option or --force every tile.
cp -p set/lat.1002.exr keep.1002.exr
expect_exit 0 "$NBRDF" bake "${set_args[@]}" -o 'set/lat.<UDIM>.exr'
check "re-run skips all" grep -Fq -- '4 tiles, 0 baked, 4 skipped' "$TMP/out"
check "skip line" grep -Fq -- 'tile 1002 (2/4): skipped, set/lat.1002.exr is up to date' "$TMP/out"
check "skipped tile untouched" cmp -s keep.1002.exr set/lat.1002.exr
touch -d '2001-01-01 00:00:00' maps/depth.1011.png
expect_exit 0 "$NBRDF" bake "${set_args[@]}" -o 'set/lat.<UDIM>.exr'
check "changed map: its tile only" grep -Fq -- '4 tiles, 1 baked, 3 skipped' "$TMP/out"
check "changed map: tile 1011 re-baked" grep -Fq -- 'tile 1011 (3/4): wrote' "$TMP/out"
expect_exit 0 "$NBRDF" bake "${set_args[@]}" --quantise 6 -o 'set/lat.<UDIM>.exr'
check "changed option: all re-baked" grep -Fq -- '4 tiles, 4 baked, 0 skipped' "$TMP/out"
expect_exit 0 "$NBRDF" bake "${set_args[@]}" --quantise 6 --force -o 'set/lat.<UDIM>.exr'
check "--force: all re-baked" grep -Fq -- '4 tiles, 4 baked, 0 skipped' "$TMP/out"

# 3. --tiles: a subset.
expect_exit 0 "$NBRDF" bake "${set_args[@]}" --tiles 1002,1011-1012 -o 'sub/lat.<UDIM>.exr'
check "--tiles: three tiles" test "$(ls sub | tr '\n' ' ')" = "lat.1002.exr lat.1011.exr lat.1012.exr "
expect_exit 2 "$NBRDF" bake "${set_args[@]}" --tiles 1003 -o 'sub/lat.<UDIM>.exr'
check "--tiles: a tile the set lacks" grep -Fq -- \
  "--tiles: tile list '1003': the set has no tile 1003 (its 4 tiles are 1001..1012)" "$TMP/err"
expect_exit 2 "$NBRDF" bake "${set_args[@]}" --tiles 1002- -o 'sub/lat.<UDIM>.exr'
check "--tiles: malformed" grep -Fq -- "tile list '1002-'" "$TMP/err"
expect_exit 2 "$NBRDF" bake $(tile_args 1001) --tiles 1001 -o sub/one.exr
check "--tiles without a set" grep -Fq -- "--tiles applies to a tile set" "$TMP/err"

# 4. Sets refused, naming the map and the tile, with nothing written.
expect_exit 1 "$NBRDF" bake "${set_args[@]}" --sigma-t 'gap/depth.<UDIM>.png' -o 'bad/lat.<UDIM>.exr'
check "a map lacking a tile: $(cat "$TMP/err")" grep -Fq -- \
  "--sigma-t 'gap/depth.<UDIM>.png' has no tile 1012 (found in --alpha1)" "$TMP/err"
expect_exit 1 "$NBRDF" bake "${set_args[@]}" --albedo 'gap/none.<UDIM>.png' -o 'bad/lat.<UDIM>.exr'
check "a pattern matching nothing" grep -Fq -- "--albedo 'gap/none.<UDIM>.png' matches no file" "$TMP/err"
expect_exit 2 "$NBRDF" bake "${set_args[@]}" -o bad/lat.exr
check "-o one file for a set" grep -Fq -- \
  "-o 'bad/lat.exr' names one file, but the inputs are a set of 4 tiles (1001..1012)" "$TMP/err"
expect_exit 2 "$NBRDF" bake $(tile_args 1001) -o 'bad/lat.<UDIM>.exr'
check "-o a pattern without a set" grep -Fq -- "is a tile pattern, but no input is a tile set" "$TMP/err"
expect_exit 2 "$NBRDF" bake "${set_args[@]}" --eta 'maps/eta.<UDIM>.<u>.png' -o 'bad/lat.<UDIM>.exr'
check "a bad pattern names the option" grep -Fq -- "--eta: " "$TMP/err"
check "nothing written for refused sets" test -z "$(ls bad)"

# 5. info of a set: a line per tile, what they share; a damaged tile fails naming it.
expect_exit 0 "$NBRDF" info 'set/lat.<UDIM>.exr'
check "info: a line per tile" grep -Eq \
  '^tile 1011: set/lat.1011.exr, 16 x 16 rgb, 5 level\(s\), half zip, [0-9]+ bytes, decoder bundle, check ok$' "$TMP/out"
check "info: the set" grep -Fq -- 'set:           set/lat.<UDIM>.exr, 4 tile(s) 1001..1012, ' "$TMP/out"
check "info: shared size" grep -Fq -- 'size:          16 x 16, 5 level(s), every tile' "$TMP/out"
check "info: shared decoder" grep -Fq -- 'decoder:       bundle, every tile' "$TMP/out"
mkdir dmg && cp set/lat.*.exr dmg/ && head -c 3000 set/lat.1002.exr >dmg/lat.1002.exr
expect_exit 1 "$NBRDF" info 'dmg/lat.<UDIM>.exr'
check "info: the damaged tile named" grep -Fq -- 'tile 1002: dmg/lat.1002.exr: FAILED: ' "$TMP/out"
check "info: the others listed" grep -Fq -- 'tile 1012: dmg/lat.1012.exr, 16 x 16 rgb' "$TMP/out"
check "info: the count" grep -Fq -- '1 of 4 tile(s) unreadable or damaged' "$TMP/err"
expect_exit 0 "$NBRDF" info set/lat.1001.exr
check "info of one tile: its fingerprint" grep -Eq '^inputs: +fnv1a64:[0-9a-f]{16}$' "$TMP/out"

# 6. verify of a set: 8 texels over 4 tiles, 2 each; tile i is sampled with seed + i, so
# its figures are those of verifying that tile alone with --texels 2 --seed i (the same
# computation: equal to the printed digits).
vargs=(--texels 8 --spp 4)
expect_exit 0 "$NBRDF" verify 'set/lat.<UDIM>.exr' "${set_args[@]}" "${vargs[@]}" --json set.json
check "verify: the sample" grep -Fq -- '4 tile(s), 8 texel(s) per level over the set (2 per tile)' "$TMP/out"
check "verify: a row per tile" grep -Eq '^  1012 +2 ' "$TMP/out"
check "verify: the set's row" grep -Eq '^  all +8 ' "$TMP/out"
expect_exit 0 "$NBRDF" verify set/lat.1011.exr $(tile_args 1011) --texels 2 --spp 4 --seed 2 \
  --json one.json
check "verify: a tile's figures are its own verify's" python3 - set.json one.json <<'PY'
import json, sys
s, o = (json.load(open(f)) for f in sys.argv[1:])
t = [t for t in s["tiles"] if t["tile"] == 1011][0]
keys = ["texels", "lobe_error_median_pct", "albedo_error_median", "reference_noise_median_pct"]
sys.exit(0 if all(t[k] == o["overall"][k] for k in keys) and s["overall"]["texels"] == 8 else 1)
PY
expect_exit 1 "$NBRDF" verify 'set/lat.<UDIM>.exr' "${set_args[@]}" --sigma-t 'gap/depth.<UDIM>.png' "${vargs[@]}"
check "verify: maps lacking a tile" grep -Fq -- "has no tile 1012" "$TMP/err"
expect_exit 2 "$NBRDF" verify set/lat.1001.exr "${set_args[@]}" "${vargs[@]}"
check "verify: one texture against patterns" grep -Fq -- "the maps are tile patterns but" "$TMP/err"
expect_exit 2 "$NBRDF" verify 'set/lat.<UDIM>.exr' "${set_args[@]}" "${vargs[@]}" --heatmap h.png
check "verify: no heat-map of a set" grep -Fq -- "--heatmap draws one texture, not a tile set" "$TMP/err"

# 7. Ctrl-C in the middle of a set, measured in work, not seconds: the bake is frozen at
# the first progress line of the second tile (the first tile is finished), SIGINT is sent
# while it is frozen, then it goes on. It exits 1 naming the tile in flight, which leaves
# no file (nor a temporary one); the tiles before it stay whole, and a re-run skips them.
mkdir big cut
for t in $tiles; do
  oiiotool --pattern fill:left=0.05:right=0.8 64x64 1 -d half -o big/rough.$t.exr
  oiiotool --pattern fill:top=0.1:bottom=4.$((t % 10)) 64x64 1 -d half -o big/depth.$t.exr
done
big_args=(--bundle bundle --alpha1 'big/rough.<UDIM>.exr' --eta 1.5 --alpha2 0.3 --r0 r0.png
  --albedo 0.7 --sigma-t 'big/depth.<UDIM>.exr' --resample bilinear)
: >run.log
"$NBRDF" bake "${big_args[@]}" --progress=json -o 'cut/lat.<UDIM>.exr' >run.log 2>&1 &
pid=$!
until grep -q '"tile_index":2' run.log || ! kill -0 $pid 2>/dev/null; do sleep 0.05; done
kill -STOP $pid 2>/dev/null
kill -INT $pid 2>/dev/null
kill -CONT $pid 2>/dev/null
wait $pid
rc=$?
check "cancel: exit 1 (got $rc)" test "$rc" = 1
inflight=$(grep -o 'cancelled in tile [0-9]*' run.log | grep -o '[0-9]*$')
check "cancel: the tile in flight is named: $(tail -2 run.log)" test -n "$inflight"
check "cancel: no file for tile $inflight" test ! -e "cut/lat.$inflight.exr"
check "cancel: only finished tiles in the folder: $(ls -a cut | tr '\n' ' ')" \
  test "$(ls -A cut | grep -vc '^lat\.[0-9]*\.exr$')" = 0
finished=$(ls cut | wc -l)
check "cancel: the first tile finished" test -e cut/lat.1001.exr
for f in cut/lat.*.exr; do
  check "cancel: $f is whole" "$NBRDF" info "$f"
done
expect_exit 0 "$NBRDF" bake "${big_args[@]}" -o 'cut/lat.<UDIM>.exr'
check "resumed: finished tiles skipped" grep -Fq -- "4 tiles, $((4 - finished)) baked, $finished skipped" "$TMP/out"

finish
