#!/usr/bin/env bash
# Cost of baking a UDIM tile set in one call against one call per tile (docs/FARM.md, "Tile
# sets"): TILES tiles of 256² made from examples/make_maps.sh's maps, each map circularly
# shifted by a different amount per tile (all-distinct painted tiles, not copies), baked at
# the fast level with the default bundle, on the CPU, OPENBLAS_NUM_THREADS=1. Each run bakes
# the set with `-o 'lat.<UDIM>.exr'` (--force), then every tile alone; the two are
# interleaved so that both see the same load. Prints wall and CPU seconds (/usr/bin/time)
# and the load average.
#   bench/tile_set_cost.sh [TILES] [RUNS] [NBRDF]   (10, 2, build/nbrdf)
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
tiles=${1:-10}
runs=${2:-2}
nbrdf=${3:-"$root/build/nbrdf"}
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1} OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
export NBRDF_DEVICE=cpu
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bash "$root/examples/make_maps.sh" "$tmp/src" >/dev/null
cd "$tmp"
mkdir maps set alone
names="alpha1.png eta.exr alpha2.png r0.png albedo.png sigma_t.exr"
for k in $(seq 0 $((tiles - 1))); do
  t=$((1001 + k))
  for f in $names; do
    oiiotool "src/$f" --cshift +$((k * 23))+$((k * 11)) -o "maps/${f%%.*}.$t.${f#*.}"
  done
done
args=(--bundle "$root/models/default" --alpha1 'maps/alpha1.<UDIM>.png'
  --eta 'maps/eta.<UDIM>.exr' --alpha2 'maps/alpha2.<UDIM>.png' --r0 'maps/r0.<UDIM>.png'
  --albedo 'maps/albedo.<UDIM>.png' --sigma-t 'maps/sigma_t.<UDIM>.exr')
timed() { /usr/bin/time -f '%e %U %S' -o "$tmp/t" "$@" >/dev/null 2>&1 || echo "FAILED: $*" >&2
  awk '{ printf "wall %.2f s, cpu %.2f s", $1, $2 + $3 }' "$tmp/t"; }
for r in $(seq 1 "$runs"); do
  echo "run $r (load $(cut -d' ' -f1-3 /proc/loadavg)):"
  echo "  set of $tiles in one call: $(timed "$nbrdf" bake "${args[@]}" --force -o 'set/lat.<UDIM>.exr')"
  : >"$tmp/sum"
  start=$(date +%s.%N)
  for k in $(seq 0 $((tiles - 1))); do
    t=$((1001 + k))
    /usr/bin/time -f '%U %S' -a -o "$tmp/sum" "$nbrdf" bake "${args[@]//<UDIM>/$t}" \
      -o "alone/lat.$t.exr" >/dev/null 2>&1 || echo "FAILED: tile $t" >&2
  done
  end=$(date +%s.%N)
  echo "  $tiles calls, one per tile:  $(awk -v s="$start" -v e="$end" \
    '{ c += $1 + $2 } END { printf "wall %.2f s, cpu %.2f s", e - s, c }' "$tmp/sum")"
done
for k in $(seq 0 $((tiles - 1))); do
  t=$((1001 + k))
  idiff -a -fail 0 -warn 0 "set/lat.$t.exr" "alone/lat.$t.exr" >/dev/null ||
    echo "tile $t: the set's texels differ from the tile baked alone" >&2
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
