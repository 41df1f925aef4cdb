#!/usr/bin/env bash
# Cost of the bake's energy audit on the sharp clearcoat of issue 33 (docs/BAKE.md, "Energy
# audit"): Blender's Clearcoat Roughness 0.05 (perceptual: alpha1 0.0025, clamped to the
# model's 0.01), IOR 1.45, Metallic 1 with Roughness and Base Color from SIZE² 8-bit images
# (what the add-on sends: alpha2 and r0 maps, albedo 0.8, sigma_t 1). Each binary bakes
# with --energy-audit 0 and with the audit on (default cap, or CAP); the runs of the two
# binaries are interleaved so that both see the same load. Prints wall and CPU seconds
# (/usr/bin/time), the load average, the worst albedo and the share of the audit.
# AUDIT_MATERIAL=examples bakes the dielectric coat of examples/make_maps.sh instead. The
# bake's own line gives how many latents the audit measured and its CPU seconds.
# BUNDLE=DIR bakes with another bundle (its own audit slopes; models/default by default).
#   bench/audit_cost.sh [SIZE] [RUNS] [CAP] NBRDF...   (128, 3, the default cap, build/nbrdf)
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
size=${1:-128}
runs=${2:-3}
cap=${3:-}
shift $(($# < 3 ? $# : 3))
bins=("$@")
[ ${#bins[@]} -gt 0 ] || bins=("$root/build/nbrdf")
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1} OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
material=${AUDIT_MATERIAL:-clearcoat}
bundle=${BUNDLE:-$root/models/default}
if [ "$material" = examples ]; then
  # The dielectric coat of examples/make_maps.sh (alpha1 0.05..0.9, eta stripes 1.3 / 1.7, a
  # copper / silver checker, painted albedo, sigma_t steps), resized to SIZE².
  bash "$root/examples/make_maps.sh" "$tmp/maps" >/dev/null
  for f in alpha1.png eta.exr alpha2.png r0.png albedo.png sigma_t.exr; do
    oiiotool "$tmp/maps/$f" --resize:filter=box "${size}x${size}" -o "$tmp/$f"
  done
  args=(--bundle "$bundle" --alpha1 "$tmp/alpha1.png" --eta "$tmp/eta.exr"
    --alpha2 "$tmp/alpha2.png" --r0 "$tmp/r0.png" --albedo "$tmp/albedo.png"
    --sigma-t "$tmp/sigma_t.exr" --range clamp)
else
  bash "$root/bench/clearcoat_maps.sh" "$size" "$tmp"
  args=(--bundle "$bundle" --roughness perceptual --alpha1 0.05 --eta 1.45
    --alpha2 "$tmp/rough.png" --r0 "$tmp/base.png" --albedo 0.8 --sigma-t 1 --range clamp)
fi

# bake LABEL NBRDF AUDIT: one bake; prints wall, CPU (user + sys) and the audit's summary.
bake() {
  /usr/bin/time -f '%e %U %S' -o "$tmp/time" "$2" bake "${args[@]}" --energy-audit "$3" \
    -o "$tmp/out.exr" >"$tmp/log" 2>&1 || { cat "$tmp/log"; return 1; }
  read -r wall user sys <"$tmp/time"
  local cpu worst
  cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.2f", u + s }')
  # "max decoded directional albedo W over N distinct latents (M measured, S CPU-s)"
  worst=$(grep -o 'max decoded directional albedo [0-9.]* over [0-9]*' "$tmp/log" | awk '{print $5, "over", $7}')
  measured=$(sed -n 's/.*distinct latents (\([0-9]*\) measured, \([0-9.]*\) CPU-s).*/\1 | \2/p' "$tmp/log")
  printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$1" "$3" "$wall" "$cpu" \
    "$(cut -d' ' -f1 /proc/loadavg)" "${worst:--}" "${measured:-- | -}"
  echo "$cpu" >>"$tmp/cpu.$1.$3"
  [ -z "$measured" ] || echo "${measured##* }" >>"$tmp/own.$1"
}

echo "$material, ${size}² maps, $runs runs, OPENBLAS_NUM_THREADS=$OPENBLAS_NUM_THREADS"
echo
echo '| binary | --energy-audit | wall s | CPU s | load | worst albedo | measured | audit CPU-s (bake'"'"'s own) |'
echo '|---|---|---|---|---|---|---|---|'
for ((r = 0; r < runs; r++)); do
  for i in "${!bins[@]}"; do
    bake "bin$i" "${bins[$i]}" 0
    bake "bin$i" "${bins[$i]}" "${cap:-16384}"
  done
done
echo
for i in "${!bins[@]}"; do
  off=$(sort -n "$tmp/cpu.bin$i.0" | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  on=$(sort -n "$tmp/cpu.bin$i.${cap:-16384}" | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  own=$(sort -n "$tmp/own.bin$i" 2>/dev/null | awk '{a[NR]=$1} END {print a[int((NR+1)/2)] + 0}')
  awk -v b="${bins[$i]}" -v i="$i" -v off="$off" -v on="$on" -v own="$own" 'BEGIN {
    printf "bin%d = %s: median CPU %.2f s off, %.2f s on: the audit %.2f CPU-s, %.0f %% of the bake",
      i, b, off, on, on - off, 100 * (on - off) / on
    if (own > 0) printf "; by the bake'"'"'s own clock %.3f CPU-s, %.0f %%", own, 100 * own / on
    printf "\n" }'
done
