#!/usr/bin/env bash
# 'nbrdf bake' and 'nbrdf info' (issue 6) on an untrained bundle and 16x16
# maps made with oiiotool: a bake with JSON progress, what info reports, and
# bad input: exit 1, a message naming the file, no output file. Each process
# start costs ~0.5 s (shared libraries), so the library cases (values,
# determinism, cancel, ranges) live in tests/bake/test_bake.c.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
"$NBRDF" bundle init bundle --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
oiiotool --pattern fill:left=0.1:right=0.6 16x16 1 -d uint8 -o alpha1.png
oiiotool --pattern checker:width=4:height=4:color1=0.9,0.6,0.5:color2=0.9,0.9,0.9 8x8 3 \
  -d uint8 -o r0.png
cp alpha1.png keep.png

base=(--bundle bundle --alpha1 alpha1.png --eta 1.5 --alpha2 0.3 --r0 0.9,0.6,0.5 --albedo 0.7
  --sigma-t 2)

# A bake with JSON progress lines for tools, then what info says about it.
expect_exit 0 "$NBRDF" bake "${base[@]}" --roughness perceptual --progress=json -o out.exr
check "json progress line" grep -Eq '^\{"event":"progress","stage":"bake","done":16,"total":16\}$' "$TMP/out"
check "json done line" grep -Eq '^\{"event":"done","output":"out.exr","width":16,"height":16,"channels":3' "$TMP/out"
check "out.exr written" test -s out.exr
"$NBRDF" info out.exr >info.txt 2>&1
check "info: size" grep -Eq '^size: +16 x 16$' info.txt
check "info: levels" grep -Eq '^levels: +5: 16x16 8x8 4x4 2x2 1x1$' info.txt
check "info: colour mode" grep -Eq '^colour mode: +rgb$' info.txt
check "info: channels" grep -Eq '^channels: +102 \(latent dim 32' info.txt
check "info: storage" grep -Eq '^storage: +half$' info.txt
check "info: model" grep -Eq '^model: +bundle \(checksum [0-9a-f]{16}\)$' info.txt
check "info: sources" grep -Fq 'alpha1=alpha1.png (png uint8 grey' info.txt
check "info: settings" grep -Fq 'roughness=perceptual' info.txt

# Bad input: exit 1, a message naming the file, no output.
expect_exit 1 "$NBRDF" bake "${base[@]}" --r0 r0.png -o bad.exr
check "mismatch names r0.png: $(cat "$TMP/err")" grep -Fq "r0.png" "$TMP/err"
check "mismatch says the CLI's option (issue 30, 4.7)" grep -Fq \
  "; pass --resample bilinear to resample the maps to one size" "$TMP/err"
# ... unless resampling is asked for: r0.png (8x8) is enlarged to 16x16.
expect_exit 0 "$NBRDF" bake "${base[@]}" --r0 r0.png --resample bilinear -o resampled.exr
check "resampled bake" test -s resampled.exr
expect_exit 0 "$NBRDF" bake "${base[@]}" --compression rle -o rle.exr
"$NBRDF" info rle.exr >info_rle.txt 2>&1
check "info: rle compression" grep -Eq '^compression: +rle$' info_rle.txt
check "settings: rle" grep -Fq 'compression=rle' info_rle.txt
check "default is zip" grep -Eq '^compression: +zip$' info.txt
expect_exit 2 "$NBRDF" bake "${base[@]}" --r0 r0.png --resample bicubic -o bad.exr
expect_exit 1 "$NBRDF" bake "${base[@]}" -o alpha1.png
check "input untouched" cmp -s alpha1.png keep.png
check "no output after failures" test ! -e bad.exr
check "no temporary files" test -z "$(ls -A | grep '\.tmp$')"

# Without --bundle, $NBRDF_BUNDLE decides; a missing or corrupt one is an error naming it,
# never a silent fallback to another bundle.
expect_exit 1 env NBRDF_BUNDLE="$TMP/nowhere" "$NBRDF" bake "${base[@]:2}" -o x.exr
check "missing \$NBRDF_BUNDLE named: $(cat "$TMP/err")" grep -Fq -- "\$NBRDF_BUNDLE=$TMP/nowhere" "$TMP/err"
check "missing \$NBRDF_BUNDLE: pass --bundle" grep -Fq -- "--bundle" "$TMP/err"
cp -r bundle broken && head -c 100 bundle/decoder.safetensors >broken/decoder.safetensors
expect_exit 1 env NBRDF_BUNDLE="$TMP/broken" "$NBRDF" bake "${base[@]:2}" -o x.exr
check "corrupt \$NBRDF_BUNDLE named: $(cat "$TMP/err")" grep -Fq -- "\$NBRDF_BUNDLE=$TMP/broken" "$TMP/err"
check "no output from a bundle error" test ! -e x.exr
expect_exit 0 env NBRDF_BUNDLE="$TMP/bundle" "$NBRDF" --version
check "--version names \$NBRDF_BUNDLE's bundle" grep -Fq "bundle: $TMP/bundle" "$TMP/out"
finish
