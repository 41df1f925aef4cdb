#!/usr/bin/env bash
# Every `nbrdf train` fit runs in one trainer (src/train/trainer.h): stopped
# with --stop-at-step and resumed by the same command, each ends with the bytes
# of a run that never stopped; a checkpoint refuses another setting, naming it
# and both values. This file: decoder and tables; test_train_resume_layering_cli.sh:
# layering and sampler. (The library-level resume tests: test_train_decoder.c,
# test_train_layering.c.)
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
export OPENBLAS_NUM_THREADS=1

D="$TMP/l2.nbds"
"$NBRDF" dataset --out "$D" --kind layered2 --count 12 --seed 5 --incident 2 --outgoing 8 \
  --spp 16 2>/dev/null
check "dataset" [ $? -eq 0 ]

# decoder: the run folder holds the checkpoint
dec=(train decoder --data "$D" --preset small --steps 20 --validation 0)
"$NBRDF" "${dec[@]}" --run "$TMP/a" >/dev/null 2>&1
expect_exit 1 "$NBRDF" "${dec[@]}" --run "$TMP/b" --stop-at-step 7
check "decoder: the stop says where and how to resume" \
  grep -q "stopped at step 7 of 20 (checkpointed; run the same command to resume)" "$TMP/err"
"$NBRDF" "${dec[@]}" --run "$TMP/b" >"$TMP/out" 2>/dev/null
check "decoder: resumed from step 7" grep -q "resumed from 7" "$TMP/out"
check "decoder: resumed bytes equal" cmp -s "$TMP/a/decoder.safetensors" "$TMP/b/decoder.safetensors"
expect_exit 1 "$NBRDF" "${dec[@]}" --run "$TMP/b" --steps 30 --lr-weights 0.001
check "decoder: another setting is refused, naming it" \
  grep -q "lr-weights = 0.002, this run has lr-weights = 0.001" "$TMP/err"

# tables
T=(train tables --decoder "$TMP/a/decoder.safetensors" --alpha-nodes 3 --eta-nodes 3 \
  --r0-nodes 3 --steps 9)
"$NBRDF" "${T[@]}" -o "$TMP/t.safetensors" --progress=json >"$TMP/tables.out" 2>/dev/null
check "tables: JSON progress on stdout in the format every command uses" \
  grep -Eq '^\{"event":"progress","stage":"[a-z ]+","done":[0-9]+,"total":[0-9]+\}$' "$TMP/tables.out"
expect_exit 1 "$NBRDF" "${T[@]}" -o "$TMP/t2.safetensors" --checkpoint "$TMP/t.ckpt" --stop-at-step 4
check "tables: no output while stopped" [ ! -e "$TMP/t2.safetensors" ]
"$NBRDF" "${T[@]}" -o "$TMP/t2.safetensors" --checkpoint "$TMP/t.ckpt" >/dev/null 2>&1
check "tables: resumed bytes equal" cmp -s "$TMP/t.safetensors" "$TMP/t2.safetensors"
expect_exit 1 "$NBRDF" "${T[@]}" -o "$TMP/t3.safetensors" --checkpoint "$TMP/t.ckpt" --seed 2 \
  --steps 12
check "tables: another seed is refused" grep -q "seed 1, this run" "$TMP/err"

expect_exit 2 "$NBRDF" "${T[@]}" -o "$TMP/t4.safetensors" --minutes x
check "a bad --minutes is named" grep -Fq -- "--minutes expects a number of minutes in [0, 1e9], got 'x'" "$TMP/err"
finish
