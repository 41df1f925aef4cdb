#!/usr/bin/env bash
# `cmake --install` (issue 20): installs the build folder of $NBRDF into a temporary prefix,
# checks the tree, builds examples/install_consumer from the installed copy with
# find_package(nbrdf) and with pkg-config, and runs them and the installed CLI from an
# unrelated folder with no --bundle (the installed bundle must be the one found), before and
# after the prefix is moved; $NBRDF_BUNDLE pointing nowhere is an error naming it.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
unset NBRDF_BUNDLE
build=$(cd "$(dirname "$NBRDF")" && pwd)
[ -f "$build/CMakeCache.txt" ] || { echo "no CMakeCache.txt beside $NBRDF" >&2; exit 1; }
libdir=$(sed -n 's/^CMAKE_INSTALL_LIBDIR:[A-Z]*=//p' "$build/CMakeCache.txt")
libdir=${libdir:-lib}
# A sanitized libnbrdf.so needs the ASan runtime loaded first in an uninstrumented program.
preload=
if grep -q '^NBRDF_SANITIZE:BOOL=ON' "$build/CMakeCache.txt"; then
  preload=$(${CC:-cc} -print-file-name=libasan.so)
fi
prefix=$TMP/prefix
if ! cmake --install "$build" --prefix "$prefix" >"$TMP/install.log" 2>&1; then
  echo "cmake --install failed:" >&2; tail -20 "$TMP/install.log" >&2; exit 1
fi

# The installed tree.
for f in bin/nbrdf "$libdir/libnbrdf.a" "$libdir/libnbrdf.so" "$libdir/cmake/nbrdf/nbrdfConfig.cmake" \
  "$libdir/cmake/nbrdf/nbrdfConfigVersion.cmake" "$libdir/pkgconfig/nbrdf.pc" \
  share/nbrdf/models/default/model.json share/nbrdf/models/default/decoder.safetensors \
  share/nbrdf/models/v1/model.json \
  share/nbrdf/shaders/nbrdf_shade.comp share/nbrdf/shaders/nbrdf_decoder.glsl \
  share/nbrdf/blender_addon/nbrdf_bake/__init__.py share/doc/nbrdf/README.md \
  share/doc/nbrdf/MODEL_BUNDLE.md share/doc/nbrdf/examples/install_consumer/main.c; do
  check "installed: $f" test -f "$prefix/$f"
done
for h in "$NBRDF_SOURCE_DIR"/include/nbrdf/*.h; do
  check "installed header $(basename "$h")" cmp -s "$h" "$prefix/include/nbrdf/$(basename "$h")"
done
check "libnbrdf.so's SONAME is libnbrdf.so.0" \
  bash -c "readelf -d '$prefix/$libdir/libnbrdf.so' | grep -Fq '[libnbrdf.so.0]'"
# Exactly the public API is exported: each exported function is declared in an installed
# header, nothing else is (an internal helper such as nn_adam_step stays local), and
# every declared function is there.
exported=$(nm -D --defined-only "$prefix/$libdir/libnbrdf.so" | awk '$2 == "T" {sub(/@.*/, "", $3); print $3}' | sort -u)
declared=$(cat "$prefix/include/nbrdf/"*.h | sed 's|/\*.*\*/||' | grep -oE 'nbrdf_[a-z0-9_]+[[:space:]]*\(' | grep -oE 'nbrdf_[a-z0-9_]+' | sort -u)
check "exported functions are the declared ones: $(diff <(echo "$exported") <(echo "$declared") | head -5 | tr '\n' ' ')" \
  test "$exported" = "$declared"
check "an internal function is not exported" bash -c "! nm -D '$prefix/$libdir/libnbrdf.so' | grep -q ' nn_adam_step'"
check "the library exports more than a handful of functions" test "$(echo "$exported" | wc -l)" -gt 30
check "installed bundle is the source tree's" \
  cmp -s "$NBRDF_SOURCE_DIR/models/default/model.json" "$prefix/share/nbrdf/models/default/model.json"

# The example, built outside the source tree from the installed copy.
example=$prefix/share/doc/nbrdf/examples/install_consumer
cp -r "$example" "$TMP/src"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if cmake -S "$TMP/src" -B "$TMP/cm" "${generator[@]}" -DCMAKE_PREFIX_PATH="$prefix" \
  >"$TMP/cm.log" 2>&1 && cmake --build "$TMP/cm" >>"$TMP/cm.log" 2>&1; then
  check "find_package build" test -x "$TMP/cm/nbrdf_consumer"
else
  check "find_package build: $(tail -5 "$TMP/cm.log")" false
fi
( cd "$TMP/src" && export PKG_CONFIG_PATH="$prefix/$libdir/pkgconfig" &&
  cc -std=c11 main.c $(pkg-config --cflags --libs nbrdf) -o "$TMP/pc_consumer" ) >"$TMP/pc.log" 2>&1
check "pkg-config build: $(tail -5 "$TMP/pc.log")" test -x "$TMP/pc_consumer"

mkdir "$TMP/elsewhere"
cd "$TMP/elsewhere"

# run_all PREFIX: the consumers and the installed CLI, no --bundle, from an unrelated folder;
# each must use PREFIX's bundle.
run_all() {
  local p=$1 tag=$2 bundle=$1/share/nbrdf/models/default
  for exe in "$TMP/cm/nbrdf_consumer" "$TMP/pc_consumer"; do
    [ -x "$exe" ] || continue
    rm -rf out && mkdir out
    expect_exit 0 env LD_LIBRARY_PATH="$p/$libdir" LD_PRELOAD="$preload" "$exe" out
    check "$tag $(basename "$exe"): bundle of the prefix: $(head -c 300 "$TMP/out")" \
      grep -Fq "bundle $bundle " "$TMP/out"
    check "$tag $(basename "$exe"): two textures" test -s out/grey.exr -a -s out/red.exr
  done
  expect_exit 0 "$p/bin/nbrdf" --version
  check "$tag --version names the installed bundle: $(cat "$TMP/out")" \
    grep -Fxq "bundle: $bundle" "$TMP/out"
  rm -f cli.exr
  expect_exit 0 "$p/bin/nbrdf" bake --alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9,0.6,0.5 \
    --albedo 0.7 --sigma-t 1 -o cli.exr
  expect_exit 0 "$p/bin/nbrdf" verify cli.exr --alpha1 0.2 --eta 1.5 --alpha2 0.3 \
    --r0 0.9,0.6,0.5 --albedo 0.7 --sigma-t 1 --texels 2
}
run_all "$prefix" installed

# A moved install finds its own bundle (not the old place, not the source tree).
mv "$prefix" "$TMP/moved"
run_all "$TMP/moved" moved

expect_exit 1 env NBRDF_BUNDLE=/nonexistent "$TMP/moved/bin/nbrdf" bake --alpha1 0.2 --eta 1.5 \
  --alpha2 0.3 --r0 0.9 --albedo 0.7 --sigma-t 1 -o never.exr
check "\$NBRDF_BUNDLE=/nonexistent named: $(cat "$TMP/err")" \
  grep -Fq '$NBRDF_BUNDLE=/nonexistent' "$TMP/err"
check "no output after a bundle error" test ! -e never.exr
if [ -x "$TMP/pc_consumer" ]; then
  expect_exit 1 env NBRDF_BUNDLE=/nonexistent LD_LIBRARY_PATH="$TMP/moved/$libdir" \
    LD_PRELOAD="$preload" "$TMP/pc_consumer" out
  check "library: \$NBRDF_BUNDLE=/nonexistent named: $(cat "$TMP/err")" \
    grep -Fq '$NBRDF_BUNDLE=/nonexistent' "$TMP/err"
fi
finish
