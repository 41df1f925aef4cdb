#!/usr/bin/env bash
# 'nbrdf render' (issue 7) on an untrained bundle: neural and reference images
# (EXR + PNG), JSON progress, the same pixels for a seed at 1 and 2 threads,
# an HDR environment file, and bad input (exit 1 or 2, no output). The
# renderer's numbers are tested in tests/eval/test_render*.c.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
"$NBRDF" bundle init bundle --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
oiiotool --pattern checker:width=4:height=4:color1=0.1:color2=0.6 16x16 1 -d uint8 -o alpha1.png
params=(--alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9,0.6,0.5 --albedo 0.7 --sigma-t 1)
"$NBRDF" bake --bundle bundle "${params[@]}" -o c.exr >/dev/null 2>&1
"$NBRDF" bake --bundle bundle --alpha1 alpha1.png --eta 1.5 --alpha2 0.3 --r0 0.9 --albedo 0.7 \
  --sigma-t 1 -o map.exr >/dev/null 2>&1
small=(--width 24 --height 16 --spp 2)

expect_exit 0 "$NBRDF" render c.exr -o n.exr --png n.png --bundle bundle "${small[@]}" --progress=json
check "json progress line" grep -Eq '^\{"event":"progress","stage":"render","done":2,"total":2\}$' "$TMP/out"
check "json done line" grep -Eq '^\{"event":"done","width":24,"height":16,"spp":2,"decoded":[1-9]' "$TMP/out"
check "png 24x16" bash -c "oiiotool --info n.png | grep -q '24 x  *16, 3 channel, uint8 png'"
check "exr float" bash -c "oiiotool --info n.exr | grep -q '24 x  *16, 3 channel, float openexr'"
expect_stderr "untrained" "$NBRDF" render c.exr -o n2.exr --bundle bundle "${small[@]}"

# 1 and 2 threads; plane scene with a mip-mapped map. The tiles, hence the networks' batches,
# are the same, but the render threads call the BLAS at the same time, and an OpenMP build of
# OpenBLAS threads a call made inside a parallel region differently (docs/RELIABILITY.md,
# "Determinism"): equal within float rounding, 1e-4 relative as in tests/render/test_render.c
# (idiff fails a value only when it is off by more than both -fail and -failrelative).
"$NBRDF" render map.exr -o t1.exr --bundle bundle --scene plane "${small[@]}" --threads 1 >/dev/null 2>&1
"$NBRDF" render map.exr -o t2.exr --bundle bundle --scene plane "${small[@]}" --threads 2 >/dev/null 2>&1
check "same pixels at 1 and 2 threads within float rounding" \
  idiff -q -fail 1e-8 -failrelative 1e-4 -warn 1e-8 -warnrelative 1e-4 t1.exr t2.exr
expect_output '5 mip levels' "$NBRDF" render map.exr -o t3.exr --bundle bundle --scene plane "${small[@]}"

# Lobe images of chosen texels.
expect_output 'wrote t3-lobe-2-3-1.png' "$NBRDF" render map.exr -o t3.exr --bundle bundle "${small[@]}" --lobe 2,3,1
check "lobe png written" test -s t3-lobe-2-3-1.png
# A texel outside the level is a bad --lobe (exit 2), like a level the texture lacks.
expect_exit 2 "$NBRDF" render map.exr -o t4.exr --bundle bundle "${small[@]}" --lobe 16,0
check "no render after a bad texel" test ! -e t4.exr
expect_exit 2 "$NBRDF" render map.exr -o t4.exr --bundle bundle --lobe 1

# Reference mode, with an HDR environment file (lat-long, 8 x 4).
oiiotool --pattern fill:top=2,2,3:bottom=0.2,0.2,0.1 8x4 3 -d float -o env.hdr
expect_exit 0 "$NBRDF" render c.exr -o r.exr --png r.png --mode reference "${params[@]}" \
  --env env.hdr --light none "${small[@]}"
check "reference exr written" test -s r.exr

# Bad input: usage errors exit 2, failures exit 1, nothing written.
expect_exit 2 "$NBRDF" render c.exr -o x.exr --mode fast
expect_exit 2 "$NBRDF" render c.exr
expect_exit 2 "$NBRDF" render c.exr -o x.exr --mode reference --alpha1 0.2
expect_exit 2 "$NBRDF" render map.exr -o x.exr --mode reference --alpha1 alpha1.png --eta 1.5 \
  --alpha2 0.3 --r0 0.9 --albedo 0.7 --sigma-t 1
expect_exit 2 "$NBRDF" render c.exr -o x.exr --light 1,2
expect_exit 1 "$NBRDF" render missing.exr -o x.exr --bundle bundle
expect_exit 1 "$NBRDF" render c.exr -o c.exr --bundle bundle
expect_exit 1 "$NBRDF" render c.exr -o x.exr --bundle bundle --env nothere.hdr "${small[@]}"
expect_stderr "nothere.hdr" "$NBRDF" render c.exr -o x.exr --bundle bundle --env nothere.hdr "${small[@]}"
check "no output after failures" test ! -e x.exr
check "input untouched" test -s c.exr
finish
