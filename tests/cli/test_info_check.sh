#!/usr/bin/env bash
# 'nbrdf info' checks the whole file by default (issue 15, item 7): a
# truncated texture or one with bytes flipped in its tiles exits 1 with a
# message naming the file (and the level and tile of a damaged one);
# --header-only reads the header alone. The damaged files are made here from
# a small bake with several tiles per level.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
"$NBRDF" bundle init bundle --seed 5 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
oiiotool --pattern fill:left=0.1:right=0.6 24x16 1 -d uint8 -o alpha1.png
"$NBRDF" bake --bundle bundle --alpha1 alpha1.png --eta 1.5 --alpha2 0.3 --r0 0.9,0.6,0.5 \
  --albedo 0.7 --sigma-t 2 --tile 8 -o good.exr >/dev/null 2>&1 ||
  { echo "bake failed" >&2; exit 1; }

expect_exit 0 "$NBRDF" info good.exr
check "info reports the full check" grep -Fq 'check:         every tile of 5 level(s) read, all values finite' "$TMP/out"
expect_exit 0 "$NBRDF" info --header-only good.exr
check "info --header-only says so" grep -Fq 'header only' "$TMP/out"

size=$(stat -c %s good.exr)
# the header of this file is a few hundred bytes; tile data fills the rest
for cut in 200 $((size / 3)) $((size / 2)) $((size * 3 / 4)) $((size - 100)) $((size - 1)); do
  head -c "$cut" good.exr >cut.exr
  expect_exit 1 "$NBRDF" info cut.exr
  check "truncated at $cut: message names the file" grep -Fq 'cut.exr' "$TMP/err"
done

# One byte inverted at a time, at offsets spread over the tile data (the last
# two thirds of the file): every one must be caught by the full check.
for frac in 40 50 60 70 80 90 97; do
  off=$((size * frac / 100))
  python3 - "$off" <<'PY'
import sys
off = int(sys.argv[1])
data = bytearray(open("good.exr", "rb").read())
data[off] ^= 0xFF
open("flip.exr", "wb").write(data)
PY
  expect_exit 1 "$NBRDF" info flip.exr
  check "flip at $off: message names the file and a level and tile" \
    grep -Eq 'flip\.exr: .*tile \([0-9]+, [0-9]+\) of level [0-9]+' "$TMP/err"
  check "flip at $off: the header was printed first" grep -Fq 'check:         FAILED' "$TMP/out"
done

# A damaged tile goes unnoticed with --header-only (that is what it skips).
expect_exit 0 "$NBRDF" info --header-only flip.exr
finish
