#!/usr/bin/env bash
# Issue 20's package check, for CI on a Debian bookworm machine as root: packages build/ with
# `cpack -G DEB`, installs the package with apt-get (its Depends resolved by apt), runs the
# installed `nbrdf bake` and `nbrdf verify` from an unrelated folder with no --bundle (the
# packaged default bundle is found), and purges the package again. Prints one line.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[ "$(id -u)" = 0 ] || { echo "test-deb-install: needs root (apt-get install)" >&2; exit 1; }
if dpkg-query -W -f='${Status}' nbrdf 2>/dev/null | grep -q "install ok installed"; then
  echo "test-deb-install: a package 'nbrdf' is already installed; remove it first" >&2
  exit 1
fi
work=$(mktemp -d)
trap 'apt-get purge -y -qq nbrdf >/dev/null 2>&1 || true; rm -rf "$work"' EXIT
cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work/pkg" >"$work/cpack.log" 2>&1 ||
  { tail -20 "$work/cpack.log" >&2; exit 1; }
deb=$(ls "$work"/pkg/nbrdf_*.deb)
export DEBIAN_FRONTEND=noninteractive
apt-get install -y -qq "$deb" >"$work/apt.log" 2>&1 || { tail -20 "$work/apt.log" >&2; exit 1; }
mkdir "$work/elsewhere" && cd "$work/elsewhere"
unset NBRDF_BUNDLE
p=(--alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9 --albedo 0.7 --sigma-t 1)
/usr/bin/nbrdf --version | grep -Fxq "bundle: /usr/share/nbrdf/models/default" ||
  { echo "test-deb-install: the installed nbrdf does not use the packaged bundle" >&2; exit 1; }
/usr/bin/nbrdf bake "${p[@]}" -o deb.exr >/dev/null
/usr/bin/nbrdf verify deb.exr "${p[@]}" --texels 2 >/dev/null
echo "test-deb-install: $(basename "$deb") installed by apt-get, bake + verify ran with its bundle, purged"
