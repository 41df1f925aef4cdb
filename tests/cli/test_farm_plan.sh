#!/usr/bin/env bash
# `nbrdf farm slurm` without a cluster: the plan it writes (plan.json's jobs, dependencies and
# resources; batch scripts bash can parse; submit.sh's chain) and what it refuses before
# writing anything. The plan run on a real cluster: tests/farm/test_farm_slurm.sh.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP" || exit 1
mkdir set
for tile in 1001 1002 1011; do
  printf 'P2\n4 2\n255\n10 20 30 40\n50 60 70 80\n' >"set/alpha1.$tile.pgm"
done
printf 'P2\n4 2\n255\n10 20 30 40\n50 60 70 80\n' >"set/alpha2.1001.pgm"
args=(--alpha1 'set/alpha1.<UDIM>.pgm' --eta 1.5 --alpha2 0.2 --r0 0.9 --albedo 0.8 --sigma-t 1)

expect_output "a plan of 3 tiles" "$NBRDF" farm slurm --plan plan -- "${args[@]}" \
  -o 'out/lat.<UDIM>.exr' --compression rle
check "no fit job at the fast level" test ! -e plan/fit.sbatch
for f in tiles.sbatch verify.sbatch submit.sh; do
  check "$f is a bash script" bash -n "plan/$f"
  check "$f is executable" test -x "plan/$f"
done
check "plan.json: tiles, dependencies, resources" python3 - <<'PY'
import json, sys
p = json.load(open("plan/plan.json"))
assert p["format"] == "nbrdf-farm-plan" and p["tiles"] == [1001, 1002, 1011], p["tiles"]
jobs = {j["name"]: j for j in p["jobs"]}
assert list(jobs) == ["tile-1001", "tile-1002", "tile-1011", "verify"], list(jobs)
t = jobs["tile-1011"]
assert t["after"] == [] and t["output"].endswith("out/lat.1011.exr"), t
cmd = t["command"]
assert cmd[1] == "bake" and "--compression=rle" in cmd, cmd
assert cmd[-4:] == ["--tiles", "1011", "-o", "out/lat.<UDIM>.exr"], cmd
assert any(a.startswith("--bundle=") for a in cmd), cmd
assert jobs["verify"]["after"] == ["tile-1001", "tile-1002", "tile-1011"]
v = jobs["verify"]["command"]
assert v[1:3] == ["verify", "out/lat.<UDIM>.exr"] and "--compression=rle" not in v, v
r = t["resources"]
assert r["cpus"] == 2 and r["memory_mib"] >= 384 and r["time_limit_s"] >= 600, r
PY
check "the tile array covers 3 tiles" grep -q '^#SBATCH --array=0-2$' plan/tiles.sbatch
check "submit.sh chains verify after the tiles" grep -q 'afterok:"$tiles" verify.sbatch' plan/submit.sh

expect_output "a plan of 2 tiles" "$NBRDF" farm slurm --plan plan2 --partition gpu --max-parallel 1 \
  -- "${args[@]}" -o 'out/lat.<UDIM>.exr' --tiles 1001,1011-1020
check "--partition reaches the scripts" grep -q '^#SBATCH --partition=gpu$' plan2/tiles.sbatch
check "--max-parallel limits the array" grep -q '^#SBATCH --array=0-1%1$' plan2/tiles.sbatch

# Refusals: exit 2 and no plan.
expect_stderr "-o 'OUT.<UDIM>.exr' is missing" "$NBRDF" farm slurm --plan bad -- "${args[@]}"
expect_exit 2 "$NBRDF" farm slurm --plan bad -- "${args[@]}" -o out/lat.exr
expect_exit 2 "$NBRDF" farm slurm --plan bad -- "${args[@]}" -o 'o.<UDIM>.exr' --bogus 1
expect_exit 2 "$NBRDF" farm slurm --plan bad -- "${args[@]}" -o 'o.<UDIM>.exr' --progress=json
expect_exit 2 "$NBRDF" farm slurm --plan bad -- --alpha1 0.1 --eta 1.5 --alpha2 0.2 --r0 0.9 \
  --albedo 0.8 --sigma-t 1 -o 'o.<UDIM>.exr'
expect_stderr "has no tile 1002" "$NBRDF" farm slurm --plan bad -- --alpha1 'set/alpha1.<UDIM>.pgm' \
  --eta 1.5 --alpha2 'set/alpha2.<UDIM>.pgm' --r0 0.9 --albedo 0.8 --sigma-t 1 -o 'o.<UDIM>.exr'
expect_exit 2 "$NBRDF" farm pbs --plan bad -- "${args[@]}"
expect_exit 2 "$NBRDF" farm slurm -- "${args[@]}" -o 'o.<UDIM>.exr'
check "nothing written by a refusal" test ! -e bad
finish
