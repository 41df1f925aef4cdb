#!/usr/bin/env bash
# 'nbrdf bake --accuracy auto --max-error P [--require]' (issue 35) with the trained default
# bundle: a target fast meets stops at fast (one level tried, said on stderr, in the JSON done
# line and in the header); a small target on a sharp low-IOR coat climbs and reports every
# level tried with its held-out error and the budget that would likely reach it; with
# --require the same is a failure (exit 1) leaving no file; usage errors for --max-error
# without auto, auto without --max-error, and auto with --fit.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
export OPENBLAS_NUM_THREADS=1
bundle=(--bundle "$NBRDF_SOURCE_DIR/models/default")
sharp=("${bundle[@]}" --alpha1 0.01 --eta 1.05 --alpha2 0.5 --r0 0.95 --albedo 1 --sigma-t 0)

expect_exit 2 "$NBRDF" bake "${sharp[@]}" --accuracy auto -o bad.exr
check "auto needs --max-error" grep -Fq -- "--accuracy auto needs --max-error" "$TMP/err"
expect_exit 2 "$NBRDF" bake "${sharp[@]}" --accuracy fitted --max-error 5 -o bad.exr
check "--max-error goes with auto" grep -Fq -- "--max-error and --require go with --accuracy auto" "$TMP/err"
expect_exit 2 "$NBRDF" bake "${sharp[@]}" --require -o bad.exr
check "--require goes with auto" grep -Fq -- "go with --accuracy auto" "$TMP/err"
expect_exit 2 "$NBRDF" bake "${sharp[@]}" --accuracy auto --max-error 0 -o bad.exr
check "--max-error 0 refused" grep -Fq -- "--max-error" "$TMP/err"
check "no file after refusals" test ! -e bad.exr

# A large target: fast meets it.
expect_exit 0 "$NBRDF" bake "${sharp[@]}" --accuracy auto --max-error 900 --budget 4 \
  --progress=json -o fast.exr
check "fast chosen (JSON)" grep -Eq '"accuracy":"fast","requested":"auto",.*"met":true,"tried":\[\{"level":"fast","heldout_error":[0-9.]+\}\]' "$TMP/out"
check "fast chosen (stderr)" grep -Eq 'auto: chose fast, held-out lobe error [0-9.]+ % \(target 900 %; tried: fast [0-9.]+ %\)' "$TMP/err"
"$NBRDF" info fast.exr >info_fast.txt 2>&1
check "header: request and outcome" grep -Eq '^accuracy: level=fast; requested=auto; chosen=fast; maxError=900; met=1; tried=fast:[0-9.]+' info_fast.txt

# A small target: climbs fitted, specialised; none meets 0.5 % at budget 4.
expect_exit 0 "$NBRDF" bake "${sharp[@]}" --accuracy auto --max-error 0.5 --budget 4 \
  --progress=json -o best.exr
check "climbed (JSON)" grep -Eq '"requested":"auto",.*"met":false,"tried":\[\{"level":"fast",[^]]*\{"level":"fitted",[^]]*\{"level":"specialised","heldout_error":[0-9.]+\}\],"suggested_budget":[0-9.e+]+' "$TMP/out"
check "not met: says so with the best and a budget" grep -Eq 'auto: no level within the budget meets 0.5 %: the best reached is [a-z]+ at [0-9.]+ % \(tried: fast [0-9.]+ %, fitted [0-9.]+ %, specialised [0-9.]+ %\); (a --budget of about [0-9.e+]+ s would likely reach it|a larger --budget is unlikely to help)' "$TMP/err"
# The level baked is the best tried (never one worse than fast): its error is the done line's.
python3 - "$TMP/out" <<'PY' || { echo "FAIL: the best level is baked" >&2; failures=$((failures + 1)); }
import json, sys
done = [json.loads(l) for l in open(sys.argv[1]) if '"done"' in l][-1]
tried = {t["level"]: t["heldout_error"] for t in done["tried"]}
fast = tried["fast"]
ok = {k: v for k, v in tried.items() if k == "fast" or v <= fast + 0.0025}
best = min(ok, key=ok.get)
assert done["accuracy"] == best, (done["accuracy"], tried)
if best != "fast":
    assert abs(done["heldout_error"] - tried[best]) < 1e-9, done
PY
"$NBRDF" info best.exr >info_best.txt 2>&1
check "header: not met, suggested budget" grep -Eq '^accuracy: level=[a-z]+; requested=auto; chosen=[a-z]+; maxError=0.5; met=0; tried=fast:[0-9.]+,fitted:[0-9.]+,specialised:[0-9.]+; suggestedBudget=' info_best.txt

# --require: the same outcome fails, and leaves no file.
expect_exit 1 "$NBRDF" bake "${sharp[@]}" --accuracy auto --max-error 0.5 --budget 4 --require \
  -o req.exr
check "--require: the message" grep -Fq "no level within the budget meets 0.5 %" "$TMP/err"
check "--require: no file" test ! -e req.exr
finish
