#!/usr/bin/env bash
# 'nbrdf bake --size WxH' (issue 21): the output size of an all-constant bake;
# maps of another size need --resample bilinear (the message says so), and
# are resampled to it (up or down); 'nbrdf verify' accepts such textures;
# bad sizes are refused with a message. Out-of-range perceptual roughness is
# reported as typed, with alpha = r^2 beside it.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
"$NBRDF" bundle init bundle --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
oiiotool --pattern fill:left=0.1:right=0.6 16x16 1 -d uint8 -o alpha1.png
consts=(--bundle bundle --alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9,0.6,0.5 --albedo 0.7
  --sigma-t 2)

# All constants: the asked size (without it, 1x1); one tuple per colour channel evaluated.
expect_exit 0 "$NBRDF" bake "${consts[@]}" --size 24x8 --progress=json -o c.exr
check "constant bake 24x8: $(tail -1 "$TMP/out")" grep -Eq '"width":24,"height":8,"channels":3,"evaluated":3[,}]' "$TMP/out"
"$NBRDF" info c.exr >info.txt 2>&1
check "info: size 24 x 8" grep -Eq '^size: +24 x 8$' info.txt
expect_exit 0 "$NBRDF" bake "${consts[@]}" --size 32 --mip-levels 1 -o square.exr
check "N means NxN" grep -Fq 'wrote square.exr: 32 x 32 rgb' "$TMP/out"
expect_exit 0 "$NBRDF" bake "${consts[@]}" -o one.exr
check "no size: 1 x 1" grep -Fq 'wrote one.exr: 1 x 1 rgb' "$TMP/out"
expect_exit 0 "$NBRDF" verify c.exr "${consts[@]:2}" --bundle bundle --spp 8 --threads 1 --texels 4
check "verify accepts the sized constant texture" grep -Fq 'verify c.exr: 24 x 8 rgb' "$TMP/out"

# A map of another size: refused without resampling, naming the map and the option.
maps=(--bundle bundle --alpha1 alpha1.png --eta 1.5 --alpha2 0.3 --r0 0.7 --albedo 0.7 --sigma-t 2)
expect_exit 1 "$NBRDF" bake "${maps[@]}" --size 32x32 -o m.exr
check "size mismatch names the map: $(cat "$TMP/err")" grep -Fq 'alpha1.png is 16x16 but the output size is 32x32' "$TMP/err"
check "size mismatch says --resample bilinear" grep -Fq -- '; pass --resample bilinear' "$TMP/err"
check "size mismatch: the option as the CLI knows it, not the C field" \
  bash -c "! grep -Fq 'nbrdf_bake_inputs' '$TMP/err'"
check "no output after the mismatch" test ! -e m.exr
# ... resampled up and down with it; verify resamples the same way.
expect_exit 0 "$NBRDF" bake "${maps[@]}" --size 32x32 --resample bilinear -o up.exr
check "enlarged to 32x32" grep -Fq 'wrote up.exr: 32 x 32 mono' "$TMP/out"
expect_exit 0 "$NBRDF" bake "${maps[@]}" --size 8x4 --resample bilinear -o down.exr
check "reduced to 8x4" grep -Fq 'wrote down.exr: 8 x 4 mono' "$TMP/out"
"$NBRDF" info up.exr >info_up.txt 2>&1
check "sources record the resampling" grep -Fq 'bilinear 16x16 -> 32x32' info_up.txt
expect_exit 0 "$NBRDF" verify up.exr "${maps[@]:2}" --bundle bundle --resample bilinear --spp 8 --threads 1 --texels 4
check "verify accepts the resampled texture" grep -Fq 'verify up.exr: 32 x 32 mono' "$TMP/out"
expect_exit 1 "$NBRDF" verify up.exr "${maps[@]:2}" --bundle bundle --spp 8 --threads 1 --texels 4
check "verify without resampling says how: $(cat "$TMP/err")" grep -Fq -- '--resample bilinear' "$TMP/err"
# The same size as the maps needs no resampling.
expect_exit 0 "$NBRDF" bake "${maps[@]}" --size 16x16 -o same.exr
check "same size as the maps" grep -Fq 'wrote same.exr: 16 x 16 mono' "$TMP/out"

# Bad sizes: usage errors naming the option and the limit.
for bad in 0x8 8x0 65537x1 -4x4 8x abc 8x8x8 1.5x2; do
  expect_exit 2 "$NBRDF" bake "${consts[@]}" --size "$bad" -o bad.exr
  check "--size $bad refused: $(cat "$TMP/err")" grep -Fq -- "--size expects WxH (or N for NxN), each an integer in [1, 65536], got '$bad'" "$TMP/err"
done
check "no output after bad sizes" test ! -e bad.exr

# Perceptual roughness out of range: the value as typed, alpha = r^2 beside it.
expect_exit 1 "$NBRDF" bake "${consts[@]}" --alpha1 3 --roughness perceptual --range refuse -o r.exr
check "typed roughness shown: $(cat "$TMP/err")" grep -Fq 'alpha1 (constant) = 3 (perceptual roughness r; alpha = r^2 = 9) is outside' "$TMP/err"
expect_exit 1 "$NBRDF" bake "${consts[@]}" --alpha1 3 --range refuse -o r.exr
check "alpha shown as typed: $(cat "$TMP/err")" grep -Fq 'alpha1 (constant) = 3 is outside' "$TMP/err"
check "no temporary files" test -z "$(ls -A | grep '\.tmp$')"
finish
