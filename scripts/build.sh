#!/usr/bin/env bash
# Configures and builds nbrdf in build/ (or $1); extra arguments go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-build}
shift || true
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNBRDF_WERROR=ON "$@" >/dev/null
cmake --build "$dir" --parallel "$(nproc)"
