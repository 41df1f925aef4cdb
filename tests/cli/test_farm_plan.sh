#!/usr/bin/env bash
# `nbrdf farm slurm` without a cluster: the plan it writes (plan.json's jobs, dependencies and
# resources; batch scripts bash can parse; submit.sh's chain) and what it refuses before
# writing anything. The plan run on a real cluster: tests/farm/test_farm_slurm.sh.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP" || exit 1
mkdir set tex
for tile in 1001 1002 1011; do
  printf 'P2\n4 2\n255\n10 20 30 40\n50 60 70 80\n' >"set/alpha1.$tile.pgm"
done
printf 'P2\n4 2\n255\n10 20 30 40\n50 60 70 80\n' >"set/alpha2.1001.pgm"
args=(--alpha1 'set/alpha1.<UDIM>.pgm' --eta 1.5 --alpha2 0.2 --r0 0.9 --albedo 0.8 --sigma-t 1)

expect_output "a plan of 3 tiles" "$NBRDF" farm slurm --plan plan -- "${args[@]}" \
  -o 'tex/lat.<UDIM>.exr' --compression rle
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
assert t["after"] == [] and t["output"].endswith("tex/lat.1011.exr"), t
cmd = t["command"]
assert cmd[1] == "bake" and "--compression=rle" in cmd, cmd
assert cmd[-4:] == ["--tiles", "1011", "-o", "tex/lat.<UDIM>.exr"], cmd
assert any(a.startswith("--bundle=") for a in cmd), cmd
assert jobs["verify"]["after"] == ["tile-1001", "tile-1002", "tile-1011"]
v = jobs["verify"]["command"]
assert v[1:3] == ["verify", "tex/lat.<UDIM>.exr"] and "--compression=rle" not in v, v
r = t["resources"]
assert r["cpus"] == 2 and r["memory_mib"] >= 384 and r["time_limit_s"] >= 600, r
PY
check "the tile array covers 3 tiles" grep -q '^#SBATCH --array=0-2$' plan/tiles.sbatch
check "submit.sh chains verify after the tiles" grep -q 'afterok:"$tiles" verify.sbatch' plan/submit.sh

expect_output "a plan of 2 tiles" "$NBRDF" farm slurm --plan plan2 --partition gpu --max-parallel 1 \
  -- "${args[@]}" -o 'tex/lat.<UDIM>.exr' --tiles 1001,1011-1020
check "--partition reaches the scripts" grep -q '^#SBATCH --partition=gpu$' plan2/tiles.sbatch
check "--max-parallel limits the array" grep -q '^#SBATCH --array=0-1%1$' plan2/tiles.sbatch

# Above fast: a fit job first, every tile bakes with its file.
expect_output "fit +1 job" "$NBRDF" farm slurm --plan plan3 -- "${args[@]}" -o 'tex/lat.<UDIM>.exr' \
  --accuracy fitted --budget 30 --compression rle
check "fit.sbatch is a bash script" bash -n plan3/fit.sbatch
check "plan.json: the fit first, tiles after it with --fit" python3 - <<'PY'
import json
p = json.load(open("plan3/plan.json"))
jobs = {j["name"]: j for j in p["jobs"]}
fit = jobs["fit"]["command"]
assert fit[1] == "fit" and "--accuracy=fitted" in fit and "--budget=30" in fit, fit
assert "--compression=rle" not in fit and fit[-2] == "-o" and fit[-1].endswith("plan3/scene.nbfit"), fit
t = jobs["tile-1002"]
assert t["after"] == ["fit"] and t["command"][-2:] == ["--fit", fit[-1]], t["command"]
PY
check "submit.sh submits the tiles after the fit" grep -q 'afterok:"$fit" tiles.sbatch' plan3/submit.sh

# Refusals: exit 2 and no plan.
expect_stderr "-o 'OUT.<UDIM>.exr' is missing" "$NBRDF" farm slurm --plan bad -- "${args[@]}"
expect_exit 2 "$NBRDF" farm slurm --plan bad -- "${args[@]}" -o tex/lat.exr
expect_exit 2 "$NBRDF" farm slurm --plan bad -- "${args[@]}" -o 'o.<UDIM>.exr' --bogus 1
expect_exit 2 "$NBRDF" farm slurm --plan bad -- "${args[@]}" -o 'o.<UDIM>.exr' --progress=json
expect_exit 2 "$NBRDF" farm slurm --plan bad -- --alpha1 0.1 --eta 1.5 --alpha2 0.2 --r0 0.9 \
  --albedo 0.8 --sigma-t 1 -o 'o.<UDIM>.exr'
expect_stderr "has no tiles 1002, 1011" "$NBRDF" farm slurm --plan bad -- --alpha1 'set/alpha1.<UDIM>.pgm' \
  --eta 1.5 --alpha2 'set/alpha2.<UDIM>.pgm' --r0 0.9 --albedo 0.8 --sigma-t 1 -o 'o.<UDIM>.exr'
expect_stderr "the folder 'nowhere' does not exist" "$NBRDF" farm slurm --plan bad -- "${args[@]}" \
  -o 'nowhere/o.<UDIM>.exr'
expect_exit 2 "$NBRDF" farm pbs --plan bad -- "${args[@]}"
expect_exit 2 "$NBRDF" farm slurm -- "${args[@]}" -o 'o.<UDIM>.exr'
check "nothing written by a refusal" test ! -e bad
finish
