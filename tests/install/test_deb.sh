#!/usr/bin/env bash
# `cpack -G DEB` (issue 20): the package of the build folder of $NBRDF depends on the runtime
# libraries it links, apt would install it here (simulated), and its contents, unpacked into a
# temporary root, run from an unrelated folder with no --bundle using the packaged bundle.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
unset NBRDF_BUNDLE
build=$(cd "$(dirname "$NBRDF")" && pwd)
for tool in cpack dpkg-deb dpkg-shlibdeps; do
  command -v $tool >/dev/null || { echo "SKIP: no $tool"; exit 0; }
done
[ -f "$build/CPackConfig.cmake" ] || { echo "no CPackConfig.cmake in $build" >&2; exit 1; }
if ! cpack -G DEB --config "$build/CPackConfig.cmake" -B "$TMP/pkg" >"$TMP/cpack.log" 2>&1; then
  echo "cpack failed:" >&2; tail -20 "$TMP/cpack.log" >&2; exit 1
fi
deb=$(ls "$TMP"/pkg/nbrdf_*.deb)
dpkg-deb -f "$deb" Depends >"$TMP/depends"
for pkg in libopenexr- libopenimageio libopencolorio libopenblas libcjson libgomp libstdc++; do
  check "Depends names $pkg: $(cat "$TMP/depends")" grep -Fq "$pkg" "$TMP/depends"
done
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
  apt-get -s install "$deb" >"$TMP/apt.log" 2>&1
  check "apt-get -s install resolves: $(tail -3 "$TMP/apt.log")" grep -q '^Inst nbrdf ' "$TMP/apt.log"
fi

dpkg-deb -x "$deb" "$TMP/root"
for f in usr/bin/nbrdf usr/include/nbrdf/model.h usr/share/nbrdf/models/default/model.json \
  usr/share/nbrdf/shaders/nbrdf_shade.comp usr/share/doc/nbrdf/README.md; do
  check "packaged: $f" test -f "$TMP/root/$f"
done
check "packaged: libnbrdf.so.0" test -e "$(ls "$TMP"/root/usr/lib*/libnbrdf.so.0 "$TMP"/root/usr/lib/*/libnbrdf.so.0 2>/dev/null | head -1)"
mkdir "$TMP/elsewhere" && cd "$TMP/elsewhere"
exe=$TMP/root/usr/bin/nbrdf
expect_exit 0 "$exe" --version
check "packaged CLI finds the packaged bundle: $(cat "$TMP/out")" \
  grep -Fxq "bundle: $TMP/root/usr/share/nbrdf/models/default" "$TMP/out"
expect_exit 0 "$exe" bake --alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9 --albedo 0.7 --sigma-t 1 \
  -o deb.exr
expect_exit 0 "$exe" verify deb.exr --alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9 --albedo 0.7 \
  --sigma-t 1 --texels 2
finish
