#!/usr/bin/env bash
# The learned albedo screen (bench/bench_audit_head.c) on bench/audit_cost.sh's two materials:
# the issue's sharp clearcoat and the dielectric coat of examples/make_maps.sh, SIZE² maps made
# exactly as audit_cost.sh makes them. Extra arguments go to the bench (before its
# --material groups); OPENBLAS_NUM_THREADS=1 as audit_cost.sh.
#   bench/audit_head.sh [SIZE] [BENCH ARGS...]   (64; build/bench/bench_audit_head)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
size=${1:-64}
shift $(($# > 0 ? 1 : 0))
bench=${BENCH:-$root/build/bench/bench_audit_head}
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1} OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# clearcoat: as audit_cost.sh
bash "$root/bench/clearcoat_maps.sh" "$size" "$tmp"
# dielectric coat: as audit_cost.sh with AUDIT_MATERIAL=examples
bash "$root/examples/make_maps.sh" "$tmp/maps" >/dev/null
for f in alpha1.png eta.exr alpha2.png r0.png albedo.png sigma_t.exr; do
  oiiotool "$tmp/maps/$f" --resize:filter=box "${size}x${size}" -o "$tmp/$f"
done
"$bench" --bundle "$root/models/default" "$@" \
  --material "clearcoat-$size" --roughness perceptual --alpha1 0.05 --eta 1.45 \
  --alpha2 "$tmp/rough.png" --r0 "$tmp/base.png" --albedo 0.8 --sigma-t 1 \
  --material "dielectric-$size" --alpha1 "$tmp/alpha1.png" --eta "$tmp/eta.exr" \
  --alpha2 "$tmp/alpha2.png" --r0 "$tmp/r0.png" --albedo "$tmp/albedo.png" \
  --sigma-t "$tmp/sigma_t.exr"
