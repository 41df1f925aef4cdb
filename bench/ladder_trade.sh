#!/usr/bin/env bash
# The accuracy ladder's trade (issue 17; docs/BAKE.md, "Accuracy levels"):
# bake time against `nbrdf verify` lobe error (median, p90, worst) for each
# level, on the example maps (examples/make_maps.sh, 256x256, verify on 64
# stratified level-0 texels) and on constant bakes of held-out `layer` BRDFs
# (bench_heldout_params), the sharp low-IOR coats (alpha1 <= 0.03,
# eta <= 1.2) marked. Prints a markdown table on stdout; logs in $WORK.
#
#   bench/ladder_trade.sh [BUILD_DIR] [WORK_DIR]
# Environment: LEVELS ("fast fitted"), CONSTANTS (held-out indices, "6 14 0 1 2 3"),
# MAPS (1: include the maps), MAPS_SIZE (256; another size resizes them with oiiotool), SPP (verify walks, 256), TEXELS (64), BUDGET (empty: default).
set -euo pipefail
source "$(dirname "$0")/bench_dirs.sh" "$@"
levels=${LEVELS:-"fast fitted"}
constants=${CONSTANTS-"6 14 0 1 2 3"} # CONSTANTS="" runs none
spp=${SPP:-256}
texels=${TEXELS:-64}
export OPENBLAS_NUM_THREADS=1 # measured: faster on the loaded 2-core machine (ARCHITECTURE.md)

# run NAME LEVEL ARGS...: bake at LEVEL, verify, print one table row.
run() {
  local name=$1 level=$2; shift 2
  local out="$work/$name.$level.exr" budget=()
  [ -n "${BUDGET:-}" ] && [ "$level" != fast ] && budget=(--budget "$BUDGET")
  /usr/bin/time -f "%e %U %S" -o "$work/$name.$level.time" \
    "$nbrdf" bake "$@" --accuracy "$level" "${budget[@]}" --progress=json -o "$out" \
    >"$work/$name.$level.bake.json" 2>"$work/$name.$level.bake.err"
  "$nbrdf" verify "$out" "$@" --texels "$texels" --spp "$spp" --json "$work/$name.$level.verify.json" \
    >"$work/$name.$level.verify.txt" 2>&1
  python3 - "$work/$name.$level" "$name" "$level" "$out" <<'PY'
import json, os, sys
base, name, level, out = sys.argv[1:5]
wall, user, sys_ = (float(x) for x in open(base + ".time").read().split()[-3:])
v = json.load(open(base + ".verify.json"))["overall"]
done = [json.loads(l) for l in open(base + ".bake.json") if '"event":"done"' in l][0]
est = "—"
if "heldout_error" in done:
    est = "%.1f %% (fast %.1f %%), %d fitted / %d held out" % (
        100 * done["heldout_error"], 100 * done["heldout_error_fast"], done["fitted_tuples"],
        done["heldout_tuples"])
print("| %s | %s | %.0f s | %.0f s | %.1f %% | %.1f %% | %.1f %% | %.1f %% | %s | %.0f KiB |" % (
    name, level, wall, user + sys_, v["lobe_error_median_pct"], v["lobe_error_p90_pct"],
    v["lobe_error_worst_pct"], v["reference_noise_median_pct"], est, os.path.getsize(out) / 1024))
PY
}

echo "| scene | level | bake wall | bake CPU | verify median | p90 | worst | ref. noise | bake's held-out estimate | file |"
echo "|---|---|---|---|---|---|---|---|---|---|"
if [ "${MAPS:-1}" = 1 ]; then
  bash "$root/examples/make_maps.sh" "$work/maps" >/dev/null
  m="$work/maps"
  if [ "${MAPS_SIZE:-256}" != 256 ]; then
    # The same maps at another size (bilinear: gradients gain distinct values, as a
    # painted map of that size would have).
    mkdir -p "$work/maps$MAPS_SIZE"
    for f in alpha1.png eta.exr alpha2.png r0.png albedo.png sigma_t.exr; do
      oiiotool "$m/$f" --resize:filter=triangle "${MAPS_SIZE}x$MAPS_SIZE" -o "$work/maps$MAPS_SIZE/$f"
    done
    m="$work/maps$MAPS_SIZE"
  fi
  maps=(--alpha1 "$m/alpha1.png" --eta "$m/eta.exr" --alpha2 "$m/alpha2.png" --r0 "$m/r0.png"
    --albedo "$m/albedo.png" --sigma-t "$m/sigma_t.exr")
  for level in $levels; do run "maps${MAPS_SIZE:+ ${MAPS_SIZE}²}" "$level" "${maps[@]}"; done
fi
"$build/bench/bench_heldout_params" 50 >"$work/heldout_params.txt"
for k in $constants; do
  line=$(awk -v k="$k" '$1 == k' "$work/heldout_params.txt")
  read -r -a args <<<"${line#* }"
  name="layer#$k"
  a1=${args[1]} eta=${args[3]}
  if python3 -c "import sys; sys.exit(0 if $a1 <= 0.03 and $eta <= 1.2 else 1)"; then
    name="layer#$k (sharp, α1 $a1, η $eta)"
  fi
  for level in $levels; do run "$name" "$level" "${args[@]}"; done
done
