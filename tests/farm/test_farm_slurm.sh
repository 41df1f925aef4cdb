#!/usr/bin/env bash
# `nbrdf farm slurm --submit` on a real one-node Slurm cluster (scripts/slurm-local.sh): a
# 4-tile set, one tile job cancelled while it bakes (no partial file), the plan submitted
# again (finished tiles skipped, the cancelled one baked, verify run), and every tile equal to
# the same set baked locally (bytes: same machine, same binary, one BLAS thread in both).
# Skipped (exit 77) when not root or when Slurm or munge is missing (scripts/setup-debian.sh).
# Prints its timings (docs/FARM.md quotes them); asserts none.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
SLURM_TEST_TOOLS=oiiotool
source "$NBRDF_SOURCE_DIR/tests/farm/slurm_lib.sh"
export OPENBLAS_NUM_THREADS=1

# The set: the example maps at 64^2, alpha1 different on each tile; tile 1003 is 384^2 so
# that its job is still baking when it is cancelled. No energy audit: on these sharp coats it
# is most of a bake (134 of 139 CPU-s for the set) and not what is tested here.
cd "$TMP" || exit 1
bash "$NBRDF_SOURCE_DIR/examples/make_maps.sh" "$TMP/src" >/dev/null
mkdir -p set farm local
for tile in 1001 1002 1003 1004; do
  n=64
  [ "$tile" = 1003 ] && n=384
  for m in eta.exr alpha2.png r0.png albedo.png sigma_t.exr; do
    oiiotool "src/$m" --resize ${n}x$n --clamp:min=0 -o "set/${m%%.*}.$tile.${m##*.}"
  done
  oiiotool --pattern fill:left=0.0$((tile % 10)):right=0.$((tile % 10 + 4)) ${n}x$n 1 -d uint8 \
    -o "set/alpha1.$tile.png"
done
args=(--alpha1 'set/alpha1.<UDIM>.png' --eta 'set/eta.<UDIM>.exr' --alpha2 'set/alpha2.<UDIM>.png'
  --r0 'set/r0.<UDIM>.png' --albedo 'set/albedo.<UDIM>.png' --sigma-t 'set/sigma_t.<UDIM>.exr'
  --energy-audit 0)

t=$(now)
if ! bash "$slurm_local" start "$cluster"; then
  echo "FAIL: the cluster did not start" >&2
  show_logs "$TMP/plan/logs"
  exit 1
fi
start_s=$(since "$t")

t=$(now)
expect_output "a plan of 4 tiles" "$NBRDF" farm slurm --plan plan --cpus 1 --verify-texels 16 --verify-spp 32 --submit -- "${args[@]}" \
  -o 'farm/lat.<UDIM>.exr'
check "plan.json lists 4 tile jobs and verify" \
  python3 -c 'import json,sys; p=json.load(open("plan/plan.json")); n=[j["name"] for j in p["jobs"]]; sys.exit(n!=["tile-1001","tile-1002","tile-1003","tile-1004","verify"])'
tiles=$(awk '$1 == "tiles" { print $2 }' plan/jobs.txt)
verify1=$(awk '$1 == "verify" { print $2 }' plan/jobs.txt)
check "jobs.txt names the array ($tiles) and verify ($verify1)" test -n "$tiles" -a -n "$verify1"
t0=$SECONDS
while [ "$(state_of "${tiles}_2")" != RUNNING ]; do
  [ $((SECONDS - t0)) -lt 120 ] || break
  sleep 0.2
done
sleep 1 # inside the bake, past its start-up
check "tile 1003's job runs ($(state_of "${tiles}_2"))" test "$(state_of "${tiles}_2")" = RUNNING
check "scancel ${tiles}_2" scancel "${tiles}_2"
check "the other tile jobs end within 300 s" wait_gone "$tiles" 300
check "tile 1003 cancelled ($(state_of "${tiles}_2"))" test "$(state_of "${tiles}_2")" = CANCELLED
check "tile 1003 left no file" test -z "$(ls farm | grep 1003)"
for tile in 1001 1002 1004; do check "tile $tile baked" test -s "farm/lat.$tile.exr"; done
check "verify waits on a tile that failed ($(state_of "$verify1"))" test "$(state_of "$verify1")" = PENDING
first_s=$(since "$t")

t=$(now)
check "the plan submitted again" bash plan/submit.sh
tiles2=$(awk '$1 == "tiles" { print $2 }' plan/jobs.txt)
verify2=$(awk '$1 == "verify" { print $2 }' plan/jobs.txt)
check "the first verify job was cancelled ($(state_of "$verify1"))" test "$(state_of "$verify1")" = CANCELLED
check "the second verify ends within 600 s" wait_gone "$verify2" 600
check "verify completed ($(state_of "$verify2"))" test "$(state_of "$verify2")" = COMPLETED
check "verify wrote its report" test -s plan/verify.json
for i in 0 1 3; do
  check "tile job $i of the re-submission skipped its finished tile" \
    grep -q skipped "plan/logs/tiles-${tiles2}_$i.log"
done
resubmit_s=$(since "$t")

t=$(now)
check "the local bake of the set" "$NBRDF" bake "${args[@]}" -o 'local/lat.<UDIM>.exr'
local_s=$(since "$t")
for tile in 1001 1002 1003 1004; do
  check "tile $tile: the farm's texture equals the local one" cmp "farm/lat.$tile.exr" "local/lat.$tile.exr"
done
check "stop" bash "$slurm_local" stop "$cluster"

[ "$failures" -eq 0 ] || show_logs "$TMP/plan/logs"
echo "timings: cluster start ${start_s} s, plan + submit + cancel ${first_s} s," \
  "re-submission to verify ${resubmit_s} s, the same set locally ${local_s} s"
finish
