#!/usr/bin/env bash
# Bad inputs through the CLI (issue 15, items 5, 6 and 10): the bad-map corpus
# (tests/texture/bad_maps/), special files given as maps, textures, bundle
# files and stdin, parameter values, and damaged textures. Each must end in a
# clean error (exit 1 or 2, a message naming the file or the parameter), never
# a hang, a crash or a sanitizer report (the suite runs this in the ASan/UBSan
# build too), and leave no output behind.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
"$NBRDF" bundle init bundle --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
bad="$NBRDF_SOURCE_DIR/tests/texture/bad_maps"
rest=(--eta 1.5 --alpha2 0.3 --r0 0.9,0.6,0.5 --albedo 0.7 --sigma-t 2)

# expect_clean_error CODE TEXT CMD...: exits CODE (under a 60 s timeout, so
# that a hang fails rather than stalls) and stderr contains TEXT.
expect_clean_error() {
  local code=$1 text=$2; shift 2
  checks=$((checks + 1))
  timeout 60 "$@" >"$TMP/out" 2>"$TMP/err" </dev/null
  local got=$?
  if [ "$got" != "$code" ] || ! grep -Fq -- "$text" "$TMP/err"; then
    echo "FAIL: '$*' exited $got (expected $code); stderr lacks '$text': $(head -c 300 "$TMP/err")" >&2
    failures=$((failures + 1))
  fi
}

# The bad-map corpus, each file as a grey and as a colour map.
for f in truncated.png bitflip.png chunk_length.png empty.png text.png truncated.exr \
  attr_length.exr two_channels.exr five_channels.exr nan.exr inf.exr negative.exr; do
  expect_clean_error 1 "alpha1: $bad/$f: " "$NBRDF" bake --bundle bundle --alpha1 "$bad/$f" \
    "${rest[@]}" -o out.exr
  expect_clean_error 1 "r0: $bad/$f: " "$NBRDF" bake --bundle bundle --alpha1 0.2 --eta 1.5 \
    --alpha2 0.3 --r0 "$bad/$f" --albedo 0.7 --sigma-t 2 -o out.exr
done
check "no output after bad maps" test ! -e out.exr
# libpng prints its own "libpng error: ..." line on stderr; the CLI folds it into its one
# message, which carries libpng's reason (issue 30, 4.7).
expect_clean_error 1 "bitflip.png: cannot read rows 0..7: PNG read error: IDAT: invalid distance" \
  "$NBRDF" bake --bundle bundle --alpha1 "$bad/bitflip.png" "${rest[@]}" -o out.exr
check "only nbrdf's lines on stderr: $(cat "$TMP/err")" bash -c "! grep -v '^nbrdf ' '$TMP/err'"

# Special files as maps: refused at once, saying what they are.
mkdir dir.png
mkfifo fifo.png
expect_clean_error 1 "alpha1: dir.png: is a directory" "$NBRDF" bake --bundle bundle \
  --alpha1 dir.png "${rest[@]}" -o out.exr
expect_clean_error 1 "alpha1: fifo.png: is a FIFO" "$NBRDF" bake --bundle bundle \
  --alpha1 fifo.png "${rest[@]}" -o out.exr
for dev in /dev/zero /dev/urandom; do
  expect_clean_error 1 "alpha1: $dev: is a character device" "$NBRDF" bake --bundle bundle \
    --alpha1 "$dev" "${rest[@]}" -o out.exr
done
# ... as a texture, an environment map, a bundle file.
expect_clean_error 1 "fifo.png: is a FIFO" "$NBRDF" render fifo.png -o r.exr --bundle bundle
expect_clean_error 1 "/dev/zero: is a character device" "$NBRDF" info /dev/zero
cp -r bundle zbundle
ln -sf /dev/zero zbundle/model.json
expect_clean_error 1 "model.json: is a character device" "$NBRDF" bake --bundle zbundle \
  --alpha1 0.2 "${rest[@]}" -o out.exr
cp -r bundle fbundle
rm fbundle/decoder.safetensors
mkfifo fbundle/decoder.safetensors
expect_clean_error 1 "decoder.safetensors: is a FIFO" "$NBRDF" bake --bundle fbundle \
  --alpha1 0.2 "${rest[@]}" -o out.exr
check "no output after special files" test ! -e out.exr

# stdin stays allowed for eval (a pipe by design), but a line is at most 64 KiB.
checks=$((checks + 1))
timeout 60 "$NBRDF" eval --model conductor </dev/zero >/dev/null 2>"$TMP/err"
if [ $? != 1 ] || ! grep -Fq "stdin: line 1 is longer than 65536 bytes" "$TMP/err"; then
  echo "FAIL: eval < /dev/zero: $(head -c 300 "$TMP/err")" >&2
  failures=$((failures + 1))
fi
printf 'alpha,r0,theta_i,phi_i,theta_o,phi_o\n0.3,0.9, 30 ,0,30,180\n' >ok.csv
checks=$((checks + 1))
"$NBRDF" eval --model conductor <ok.csv >/dev/null 2>"$TMP/err" ||
  { echo "FAIL: eval with a spaced number: $(cat "$TMP/err")" >&2; failures=$((failures + 1)); }
for v in 0x10 1e400 nan; do
  printf 'alpha,r0,theta_i,phi_i,theta_o,phi_o\n0.3,0.9,%s,0,30,180\n' "$v" >bad.csv
  checks=$((checks + 1))
  "$NBRDF" eval --model conductor <bad.csv >/dev/null 2>"$TMP/err"
  if [ $? != 1 ] || ! grep -Fq "stdin:2: column 'theta_i' expects a number in [0, 90), got '$v'" "$TMP/err"; then
    echo "FAIL: eval '$v': $(cat "$TMP/err")" >&2
    failures=$((failures + 1))
  fi
done

# eval --in reads its CSV once, from start to end, as it reads stdin: a pipe (process
# substitution) and a named FIFO are accepted; devices and directories are not (issue 30, 4.7).
checks=$((checks + 1))
timeout 60 "$NBRDF" eval --model conductor --in <(cat ok.csv) >"$TMP/out" 2>"$TMP/err"
if [ $? != 0 ] || ! grep -q '^0.3,0.9, 30 ,0,30,180,' "$TMP/out"; then
  echo "FAIL: eval --in <(cat ok.csv): $(head -c 300 "$TMP/err")" >&2
  failures=$((failures + 1))
fi
mkfifo in.fifo
(sleep 1; cat ok.csv >in.fifo) &
checks=$((checks + 1))
timeout 60 "$NBRDF" eval --model conductor --in in.fifo >"$TMP/out" 2>"$TMP/err"
if [ $? != 0 ] || ! grep -q '^0.3,0.9, 30 ,0,30,180,' "$TMP/out"; then
  echo "FAIL: eval --in a named FIFO written later: $(head -c 300 "$TMP/err")" >&2
  failures=$((failures + 1))
fi
wait
expect_clean_error 1 "/dev/zero: is a character device" "$NBRDF" eval --model conductor \
  --in /dev/zero
expect_clean_error 1 "dir.png: is a directory" "$NBRDF" eval --model conductor --in dir.png

# Parameter values: a number with white space around it is a number; hex,
# inf and nan are not numbers; out of a float's range is an error naming the
# parameter; a file named like a hex number that exists is a map.
expect_exit 0 "$NBRDF" bake --bundle bundle --alpha1 "0.1 " "${rest[@]}" -o spaced.exr
check "spaced value is a constant" grep -q "alpha1=0.1" <("$NBRDF" info spaced.exr 2>&1)
expect_clean_error 2 "alpha1: '0x10' is neither a number" "$NBRDF" bake --bundle bundle \
  --alpha1 0x10 "${rest[@]}" -o out.exr
expect_clean_error 2 "alpha1: 'inf' is neither a number" "$NBRDF" bake --bundle bundle \
  --alpha1 inf "${rest[@]}" -o out.exr
expect_clean_error 2 "alpha1: '1e-400' is too small" "$NBRDF" bake --bundle bundle \
  --alpha1 1e-400 "${rest[@]}" -o out.exr
expect_clean_error 2 "sigma_t: '1e400' is too large" "$NBRDF" bake --bundle bundle \
  --alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9 --albedo 0.7 --sigma-t 1e400 -o out.exr
expect_clean_error 2 "--width" "$NBRDF" render spaced.exr -o r.exr --bundle bundle --width 0x10
cp "$bad/grey_alpha0.png" 0x10
expect_exit 0 "$NBRDF" bake --bundle bundle --alpha1 0x10 "${rest[@]}" -o hexfile.exr
check "no output after bad values" test ! -e out.exr

# An OpenEXR map whose data window is not its display window (made here: smaller, then shifted)
# is refused naming both windows, not baked at the data window's size (issue 30, 4.7).
oiiotool --pattern constant:color=0.3 8x8 1 -d half --fullsize 16x16+0+0 -o window.exr
expect_clean_error 1 \
  "alpha1: window.exr: data window 8x8 at (0, 0), display window 16x16 at (0, 0); expected" \
  "$NBRDF" bake --bundle bundle --alpha1 window.exr "${rest[@]}" -o out.exr
oiiotool --pattern constant:color=0.3 8x8 1 -d half --origin +2+2 --fullsize 8x8+0+0 \
  -o shifted.exr
expect_clean_error 1 "shifted.exr: data window 8x8 at (2, 2), display window 8x8 at (0, 0)" \
  "$NBRDF" bake --bundle bundle --alpha1 shifted.exr "${rest[@]}" -o out.exr
oiiotool window.exr --croptofull -o full.exr
expect_exit 0 "$NBRDF" bake --bundle bundle --alpha1 full.exr "${rest[@]}" -o full-lat.exr
check "the padded map bakes at the display window's size" grep -q "wrote full-lat.exr: 16 x 16" \
  "$TMP/out"
check "no output after a windowed map" test ! -e out.exr

# Messages name the right file: --png equal to the input, a map too large.
expect_clean_error 1 "spaced.exr: the output is the input 'spaced.exr'" "$NBRDF" render spaced.exr -o r.exr --png spaced.exr \
  --bundle bundle
oiiotool --pattern constant:color=0.3 65537x1 1 -d uint8 -o wide.png
expect_clean_error 1 "alpha1: wide.png is 65537x1" "$NBRDF" bake --bundle bundle \
  --alpha1 wide.png "${rest[@]}" -o out.exr

# Mip levels and texels the texture lacks (issue 30, 4.7): one message whatever the number's
# size, naming the texture's levels; --lobe says what each field is.
expect_exit 0 "$NBRDF" bake --bundle bundle --alpha1 0.2 "${rest[@]}" --size 64x64 -o l64.exr
vrest=(--bundle bundle --alpha1 0.2 "${rest[@]}" --texels 1 --spp 2)
for l in 7 32 99 99999999999999999999; do
  expect_clean_error 2 "--level: l64.exr has 7 mip levels (0..6); there is no level $l" \
    "$NBRDF" verify l64.exr "${vrest[@]}" --level "$l"
done
expect_clean_error 2 "--level expects a mip level (an integer, 0 the full size) or 'all', got '-1'" \
  "$NBRDF" verify l64.exr "${vrest[@]}" --level -1
printf 'u,v,theta_i,phi_i,theta_o,phi_o\n0.5,0.5,30,0,30,180\n' >q.csv
expect_clean_error 2 "--level: l64.exr has 7 mip levels (0..6); there is no level 99" \
  "$NBRDF" eval --texture l64.exr --bundle bundle --level 99 --in q.csv
rr=(l64.exr -o r.exr --bundle bundle --width 4 --height 4 --spp 1)
expect_clean_error 2 "--lobe 1,1,99: l64.exr has 7 mip levels (0..6); there is no level 99" \
  "$NBRDF" render "${rr[@]}" --lobe 1,1,99
expect_clean_error 2 "--lobe 1,1,99999999999999999999: l64.exr has 7 mip levels (0..6)" \
  "$NBRDF" render "${rr[@]}" --lobe 1,1,99999999999999999999
expect_clean_error 2 \
  "--lobe 64,1: level 0 of l64.exr is 64 x 64 texels (X 0..63, Y 0..63); there is no texel (64, 1)" \
  "$NBRDF" render "${rr[@]}" --lobe 64,1
expect_clean_error 2 "level 2 of l64.exr is 16 x 16 texels (X 0..15, Y 0..15)" \
  "$NBRDF" render "${rr[@]}" --lobe 3,16,2
expect_clean_error 2 "the column X and row Y of a texel of mip level LEVEL" \
  "$NBRDF" render "${rr[@]}" --lobe 1,-1
check "no render after bad --lobe" test ! -e r.exr

# --budget below the level's smallest plan is a bad option (exit 2), said once: not
# "nbrdf bake: bake: ..." (issue 30, 4.7).
expect_clean_error 2 "nbrdf bake: --budget: a budget of 1e-300 s is too small for 'compact'" \
  "$NBRDF" bake --bundle bundle --alpha1 0.2 "${rest[@]}" --accuracy compact --budget 1e-300 \
  -o out.exr
check "budget: no doubled prefix" bash -c "! grep -Fq 'bake: bake:' '$TMP/err'"

# Numeric options out of their range are usage errors (exit 2), caught by the CLI rather
# than refused later by the library (exit 1) (issue 30, 4.7).
oiiotool --pattern constant:color=0.5 4x4 1 -d uint8 -o eta8.png
expect_clean_error 2 "--eta-range expects LO,HI with LO < HI (numbers, LO >= 0), got '-1,2'" \
  "$NBRDF" bake --bundle bundle --alpha1 0.2 --eta eta8.png --alpha2 0.3 --r0 0.9 --albedo 0.7 \
  --sigma-t 2 --eta-range -1,2 -o out.exr
expect_clean_error 2 "--sigma-t-range expects LO,HI" "$NBRDF" bake --bundle bundle --alpha1 0.2 \
  "${rest[@]}" --sigma-t-range 0,1e39 -o out.exr
expect_clean_error 2 "--r0 '0.9,1.5,0.5': 1.5 is above 1 (not physical); expected a reflectance" \
  "$NBRDF" bake --bundle bundle --alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9,1.5,0.5 \
  --albedo 0.7 --sigma-t 2 -o out.exr
expect_clean_error 2 "--alpha1 '-0.2': -0.2 is negative; expected a value >= 0" "$NBRDF" bake \
  --bundle bundle --alpha1 -0.2 "${rest[@]}" -o out.exr
expect_clean_error 2 "--env-scale expects a number in [0, 3.4e38], got '1e39'" "$NBRDF" render \
  spaced.exr -o r.exr --bundle bundle --env-scale 1e39
check "no output after bad numeric options" test ! -e out.exr

# A path of ~4000 bytes (16 components of 250) does not push a message's reason out of the
# 512-byte error buffer: the path's middle gives way to an ellipsis (issue 30, 4.3).
long=ln
for k in $(seq 16); do long="$long/$(printf '%0250d' "$k")"; done
mkdir -p "$long"
echo hello >"$long/x.exr"
expect_clean_error 1 "/x.exr: not a readable OpenEXR file: Unable to read magic" "$NBRDF" info \
  "$long/x.exr"
expect_clean_error 1 "/nodir': No such file or directory" "$NBRDF" bake --bundle bundle \
  --alpha1 0.2 "${rest[@]}" -o "$long/nodir/x.exr"
check "long path: elided with an ellipsis" grep -Fq "…" "$TMP/err"
rm -rf ln

# Damaged textures (made here from a bake, deterministically): truncated and
# bit-flipped files through info, render and verify end in exit 0 or 1, never
# a crash; a refusal names the file.
"$NBRDF" bake --bundle bundle --alpha1 "$bad/rgba_alpha0.png" "${rest[@]}" -o good.exr \
  >/dev/null 2>&1
size=$(stat -c %s good.exr)
for cut in 8 64 200 $((size / 2)) $((size - 1)); do
  head -c "$cut" good.exr >"cut$cut.exr"
done
for at in 40 120 300 $((size / 2)) $((size - 8)); do
  cp good.exr "flip$at.exr"
  printf '\xff' | dd of="flip$at.exr" bs=1 seek="$at" conv=notrunc status=none
done
for t in cut*.exr flip*.exr; do
  for cmd in "info $t" "render $t -o r.exr --bundle bundle --width 8 --height 8 --spp 1" \
    "verify $t --bundle bundle --alpha1 $bad/rgba_alpha0.png ${rest[*]} --texels 2 --spp 4 --threads 1"; do
    checks=$((checks + 1))
    # shellcheck disable=SC2086
    timeout 120 "$NBRDF" $cmd >/dev/null 2>"$TMP/err"
    rc=$?
    if [ $rc -gt 1 ] || { [ $rc = 1 ] && ! grep -Fq "$t" "$TMP/err"; }; then
      echo "FAIL: '$cmd' exited $rc: $(head -c 300 "$TMP/err")" >&2
      failures=$((failures + 1))
    fi
  done
done
finish
