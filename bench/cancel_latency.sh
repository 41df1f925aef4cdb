#!/usr/bin/env bash
# Seconds from Ctrl-C to exit for every long command (docs/RELIABILITY.md, "Cancel and progress": the promise is 1 s). A measurement,
# not a test: the tests assert work after the signal (tests/cli/test_cancel.sh), which a
# loaded machine cannot fail; these seconds depend on the load, so say it with them.
#   bench/cancel_latency.sh [NBRDF] [DELAY]   (DELAY: seconds of work before SIGINT, 1)
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
nbrdf=${1:-$root/build/nbrdf}
delay=${2:-1}
bundle=$root/models/default
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"

# measure WHAT CMD...: SIGINT DELAY s after the first progress line; prints the seconds to
# exit.
measure() {
  local what=$1; shift
  : >run.log
  "$@" >run.log 2>&1 </dev/null &
  local pid=$!
  until grep -q '"progress"' run.log 2>/dev/null || ! kill -0 $pid 2>/dev/null; do sleep 0.02; done
  sleep "$delay"
  local t0 t1
  t0=$(date +%s.%N)
  kill -INT $pid 2>/dev/null
  wait $pid
  local rc=$?
  t1=$(date +%s.%N)
  printf '%-14s exit %d  %.2f s after SIGINT  (load %s)\n' "$what" $rc \
    "$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')" "$(cut -d' ' -f1 /proc/loadavg)"
}

oiiotool --pattern noise:type=uniform:min=0.05:max=0.9 1024x1024 1 -d float -o alpha1.exr
"$nbrdf" bake --bundle "$bundle" --alpha1 0.3 --eta 1.5 --alpha2 0.3 --r0 0.8 --albedo 0.7 \
  --sigma-t 2 -o one.exr >/dev/null 2>&1
measure "bake 1024²" "$nbrdf" bake --bundle "$bundle" --alpha1 alpha1.exr --eta 1.5 --alpha2 0.3 \
  --r0 0.8 --albedo 0.7 --sigma-t 2 --progress=json -o big.exr
measure verify "$nbrdf" verify one.exr --bundle "$bundle" --alpha1 0.3 --eta 1.5 --alpha2 0.3 \
  --r0 0.8 --albedo 0.7 --sigma-t 2 --spp 200000 --progress=json
measure render "$nbrdf" render one.exr --bundle "$bundle" -o image.exr --width 64 --height 64 \
  --spp 200000 --progress=json
measure dataset "$nbrdf" dataset --out data.bin --kind layered2 --count 50 --seed 1 --spp 4096 \
  --progress=json
measure "train tables" "$nbrdf" train tables --decoder "$bundle/decoder.safetensors" \
  -o tables.safetensors --steps 100000 --progress=json
