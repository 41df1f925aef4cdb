#!/usr/bin/env bash
# --accuracy auto --max-error P (issue 35; docs/BAKE.md, "auto"): for the example maps (at
# MAPS_SIZE², default 64) and three constant scenes (a car-paint-like coat, a low-IOR varnish, a
# sharp lacquer over metal), each level alone (fast, fitted, specialised at BUDGET) and auto at
# each P in TARGETS: bake wall seconds, the level baked, the bake's held-out lobe error and
# `nbrdf verify`'s median lobe error (TEXELS texels, SPP walks). Prints a markdown table on
# stdout; logs and textures in WORK_DIR.
#
#   bench/accuracy_auto.sh [BUILD_DIR] [WORK_DIR]
# Environment: BUDGET (20), TARGETS ("10 5 3"), MAPS_SIZE (64), TEXELS (8), SPP (256),
# SCENES ("maps carpaint varnish lacquer").
set -euo pipefail
source "$(dirname "$0")/bench_dirs.sh" "$@"
budget=${BUDGET:-20}
targets=${TARGETS:-"10 5 3"}
size=${MAPS_SIZE:-64}
texels=${TEXELS:-8}
spp=${SPP:-256}
scenes=${SCENES:-"maps carpaint varnish lacquer"}
export OPENBLAS_NUM_THREADS=1 # measured: faster on the loaded 2-core machine (ARCHITECTURE.md)
export NBRDF_BUNDLE=${NBRDF_BUNDLE:-$root/models/default}

# run SCENE TAG BAKE-ARGS... -- SCENE-ARGS...: bake, verify, one table row.
run() {
  local scene=$1 tag=$2; shift 2
  local bake=()
  while [ "$1" != -- ]; do bake+=("$1"); shift; done
  shift
  local safe=${tag//[ =]/_}
  local base="$work/$scene.$safe" out="$work/$scene.$safe.exr"
  /usr/bin/time -f "%e" -o "$base.time" \
    "$nbrdf" bake "$@" "${bake[@]}" --progress=json -o "$out" >"$base.bake.json" 2>"$base.bake.err"
  "$nbrdf" verify "$out" "$@" --texels "$texels" --spp "$spp" --json "$base.verify.json" \
    >"$base.verify.txt" 2>&1
  python3 - "$base" "$scene" "$tag" <<'PY'
import json, sys
base, scene, tag = sys.argv[1:4]
wall = float(open(base + ".time").read().split()[-1])
v = json.load(open(base + ".verify.json"))["overall"]
done = [json.loads(l) for l in open(base + ".bake.json") if '"event":"done"' in l][0]
level = done.get("accuracy", "fast")
held = "—"
if "heldout_error" in done:
    err = done["heldout_error"] if level != "fast" else done["heldout_error_fast"]
    held = "%.1f %%" % (100 * err)
tried = ""
if done.get("requested") == "auto":
    tried = ", ".join("%s %.1f" % (t["level"], 100 * t["heldout_error"]) for t in done["tried"])
    tried += "" if done["met"] else " (not met)"
if done.get("fell_back"):
    level += " (fell back from %s, %.1f %%)" % (done["requested"], 100 * done["heldout_error"])
print("| %s | %s | %.0f s | %s | %s | %.1f %% | %.1f %% | %s |" % (
    scene, tag, wall, level, held, v["lobe_error_median_pct"],
    v["reference_noise_median_pct"], tried))
PY
}

args_of() {
  case $1 in
  maps)
    bash "$root/examples/make_maps.sh" "$work/maps256" >/dev/null
    mkdir -p "$work/maps"
    for f in alpha1.png eta.exr alpha2.png r0.png albedo.png sigma_t.exr; do
      oiiotool "$work/maps256/$f" --resize:filter=triangle "${size}x$size" -o "$work/maps/$f"
    done
    m="$work/maps"
    echo --alpha1 "$m/alpha1.png" --eta "$m/eta.exr" --alpha2 "$m/alpha2.png" --r0 "$m/r0.png" \
      --albedo "$m/albedo.png" --sigma-t "$m/sigma_t.exr" ;;
  # A clear coat over a rough tinted conductor (metallic car paint's base).
  carpaint) echo --alpha1 0.1 --eta 1.5 --alpha2 0.3 --r0 0.8,0.25,0.2 --albedo 1 --sigma-t 0 ;;
  # A thin low-IOR varnish, slightly tinted, over a rough conductor.
  varnish) echo --alpha1 0.05 --eta 1.15 --alpha2 0.4 --r0 0.7,0.5,0.3 --albedo 0.9,0.7,0.4 --sigma-t 0.5 ;;
  # A sharp lacquer over polished metal.
  lacquer) echo --alpha1 0.02 --eta 1.5 --alpha2 0.15 --r0 0.95,0.9,0.85 --albedo 1 --sigma-t 0 ;;
  esac
}

echo "| scene | run | bake wall | level baked | bake's held-out error | verify median | ref. noise | auto tried (held-out %) |"
echo "|---|---|---:|---|---:|---:|---:|---|"
for scene in $scenes; do
  read -r -a a <<<"$(args_of "$scene")"
  run "$scene" fast --accuracy fast -- "${a[@]}"
  for level in fitted specialised; do
    run "$scene" "$level" --accuracy "$level" --budget "$budget" -- "${a[@]}"
  done
  for p in $targets; do
    run "$scene" "auto P=$p" --accuracy auto --max-error "$p" --budget "$budget" -- "${a[@]}"
  done
done
