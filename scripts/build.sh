#!/usr/bin/env bash
# Configures and builds nbrdf in build/ (or $1); extra arguments go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-build}
shift || true
# ccache, where installed, makes rebuilds in several checkouts of one tree cheap.
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNBRDF_WERROR=ON "${launcher[@]}" "$@" >/dev/null
cmake --build "$dir" --parallel "$(nproc)"
