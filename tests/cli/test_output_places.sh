#!/usr/bin/env bash
# Every output's place is checked before any work (issue 30, part 4): a folder that does
# not exist, a name longer than NAME_MAX and a read-only file system are refused before
# the first progress line (they used to fail after the whole bake, render or verify, and
# render left its EXR when the PNG's folder was missing); a name of NAME_MAX bytes can be
# replaced (its temporary name used to be too long). On a read-only mount the message
# says so instead of "make it writable". The read-only mount needs root; skipped without.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
bundle="$NBRDF_SOURCE_DIR/models/default"
one=(--alpha1 0.3 --eta 1.5 --alpha2 0.3 --r0 0.8 --albedo 0.7 --sigma-t 2)
"$NBRDF" bake --bundle "$bundle" "${one[@]}" -o tex.exr >/dev/null ||
  { echo "FAIL: bake of the input texture" >&2; exit 1; }

# before_work WHAT TEXT CMD...: exit 1, stderr holds TEXT, and no progress line came first.
before_work() {
  local what=$1 text=$2; shift 2
  expect_exit 1 "$@"
  check "$what: message has '$text': $(head -c 300 "$TMP/err")" grep -Fq -- "$text" "$TMP/err"
  check "$what: refused before any work: $(grep -c progress "$TMP/out") progress lines" \
    test "$(grep -c '"progress"' "$TMP/out")" = 0
}

mkdir dest
before_work "render --png into a missing folder" "nonexist/r.png: " \
  "$NBRDF" render tex.exr --bundle "$bundle" -o dest/r.exr --png nonexist/r.png --width 16 \
  --height 16 --spp 1 --progress=json
check "render: no EXR without its PNG" test ! -e dest/r.exr
before_work "verify --json into a missing folder" "nonexist/v.json: " \
  "$NBRDF" verify tex.exr --bundle "$bundle" "${one[@]}" --spp 16 --json nonexist/v.json \
  --progress=json
before_work "verify --heatmap into a missing folder" "No such file or directory" \
  "$NBRDF" verify tex.exr --bundle "$bundle" "${one[@]}" --spp 16 --json dest/v.json \
  --heatmap nonexist/h.png --progress=json
check "verify: no JSON without its heat-map" test ! -e dest/v.json

long256=$(printf 'n%.0s' $(seq 252)).exr # 256 bytes
long255=$(printf 'n%.0s' $(seq 251)).exr # 255 bytes: NAME_MAX
before_work "bake -o a 256-byte name" "File name too long" \
  "$NBRDF" bake --bundle "$bundle" "${one[@]}" --progress=json -o "dest/$long256"
expect_exit 0 "$NBRDF" bake --bundle "$bundle" "${one[@]}" -o "dest/$long255"
cp "dest/$long255" first.exr
expect_exit 0 "$NBRDF" bake --bundle "$bundle" "${one[@]}" --albedo 0.5 -o "dest/$long255"
differ() { ! cmp -s "$1" "$2"; }
check "a 255-byte name was replaced" differ "dest/$long255" first.exr
check "no temporary file left: $(ls -A dest | grep -c tmp)" test "$(ls -A dest | grep -c tmp)" = 0

if [ "$(id -u)" = 0 ] && mkdir ro && mount -t tmpfs -o size=64k tmpfs ro 2>/dev/null; then
  trap 'umount "$TMP/ro" 2>/dev/null; rm -rf "$TMP"' EXIT
  echo keep >ro/old.exr
  chmod 0644 ro/old.exr
  mount -o remount,ro "$TMP/ro"
  before_work "bake over a 0644 file on a read-only mount" "Read-only file system" \
    "$NBRDF" bake --bundle "$bundle" "${one[@]}" --progress=json -o ro/old.exr
  no_advice() { ! grep -Fq "make it writable" "$TMP/err"; }
  check "read-only mount: no advice to make the file writable" no_advice
  check "read-only mount: file kept" grep -q keep ro/old.exr
  before_work "bake into a read-only mount" "Read-only file system" \
    "$NBRDF" bake --bundle "$bundle" "${one[@]}" --progress=json -o ro/new.exr
else
  echo "SKIP: read-only mount (needs root to mount a tmpfs)"
fi
finish
