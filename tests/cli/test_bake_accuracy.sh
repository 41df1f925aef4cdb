#!/usr/bin/env bash
# 'nbrdf bake --accuracy/--budget/--seed' (issue 17) on an untrained bundle:
# the fast level writes the same bytes as a bake without the options; bad
# levels and budgets are refused with a message and leave no file; a fitted
# bake reports its held-out error (JSON done line, stage progress) and
# 'nbrdf info' prints the nbrdf:accuracy attribute. The library cases
# (errors below fast's, determinism, cancel) are in tests/bake/test_bake_accuracy.c.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
export OPENBLAS_NUM_THREADS=1
"$NBRDF" bundle init bundle --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
base=(--bundle bundle --alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9 --albedo 0.7 --sigma-t 1)

expect_exit 0 "$NBRDF" bake "${base[@]}" -o plain.exr
expect_exit 0 "$NBRDF" bake "${base[@]}" --accuracy fast -o fast.exr
check "fast bytes equal a bake without --accuracy" cmp -s plain.exr fast.exr

expect_exit 2 "$NBRDF" bake "${base[@]}" --accuracy best -o bad.exr
check "--accuracy message" grep -Fq -- "--accuracy expects fast, fitted, specialised, compact or auto, got 'best'" "$TMP/err"
for b in 0 -3 abc nan 1e9; do
  expect_exit 2 "$NBRDF" bake "${base[@]}" --accuracy fitted --budget "$b" -o bad.exr
  check "--budget $b message" grep -Fq -- "--budget expects a number of seconds" "$TMP/err"
done
expect_exit 2 "$NBRDF" bake "${base[@]}" --budget 10 -o bad.exr
check "--budget without a level" grep -Fq "applies to --accuracy fitted, specialised, compact or auto" "$TMP/err"
expect_exit 2 "$NBRDF" bake "${base[@]}" --accuracy fitted --budget 0.2 -o bad.exr
check "too small a budget says what fits" grep -Fq "too small for 'fitted'" "$TMP/err"
check "no file after refusals" test ! -e bad.exr

expect_exit 0 "$NBRDF" bake "${base[@]}" --accuracy fitted --budget 2 --seed 5 --progress=json \
  -o fitted.exr
check "ground truth stage" grep -Fq '"stage":"ground truth"' "$TMP/out"
check "fit stage" grep -Fq '"stage":"fit"' "$TMP/out"
check "done line reports the level" \
  grep -Eq '"accuracy":"fitted","requested":"fitted","fell_back":false,"budget":2,"distinct":1,"fitted_tuples":1,"heldout_tuples":1,"heldout_error":[0-9.]+' "$TMP/out"
"$NBRDF" info fitted.exr >info.txt 2>&1
check "info prints the accuracy" grep -Eq '^accuracy: level=fitted; budget=2; .*seed=5$' info.txt
"$NBRDF" info plain.exr >info_plain.txt 2>&1
check "a fast bake has no accuracy line" bash -c '! grep -q "^accuracy:" info_plain.txt'
finish
