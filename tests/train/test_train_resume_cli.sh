#!/usr/bin/env bash
# Every `nbrdf train` fit runs in one trainer (src/train/trainer.h): stopped
# with --stop-at-step and resumed by the same command, each ends with the bytes
# of a run that never stopped; a checkpoint refuses another setting, naming it
# and both values. (The library-level resume tests: test_train_decoder.c and
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
"$NBRDF" "${T[@]}" -o "$TMP/t.safetensors" >/dev/null 2>&1
expect_exit 1 "$NBRDF" "${T[@]}" -o "$TMP/t2.safetensors" --checkpoint "$TMP/t.ckpt" --stop-at-step 4
check "tables: no output while stopped" [ ! -e "$TMP/t2.safetensors" ]
"$NBRDF" "${T[@]}" -o "$TMP/t2.safetensors" --checkpoint "$TMP/t.ckpt" >/dev/null 2>&1
check "tables: resumed bytes equal" cmp -s "$TMP/t.safetensors" "$TMP/t2.safetensors"
expect_exit 1 "$NBRDF" "${T[@]}" -o "$TMP/t3.safetensors" --checkpoint "$TMP/t.ckpt" --seed 2 \
  --steps 12
check "tables: another seed is refused" grep -q "seed 1, this run" "$TMP/err"

# layering, both losses (a stop inside an epoch: 11 pairs in batches of 4 = 3 a epoch)
C=(train layering --data "$D" --tables "$TMP/t.safetensors" --batch 4 --rows 8 --epochs 4)
for loss in latent decoded; do
  extra=(--run "$TMP/a" --loss "$loss")
  "$NBRDF" "${C[@]}" "${extra[@]}" -o "$TMP/$loss.safetensors" >/dev/null 2>&1
  expect_exit 1 "$NBRDF" "${C[@]}" "${extra[@]}" -o "$TMP/${loss}2.safetensors" \
    --checkpoint "$TMP/$loss.ckpt" --stop-at-step 5
  check "layering $loss: stopped inside epoch 2" grep -q "in epoch 2 after batch 2 of 3" "$TMP/err"
  "$NBRDF" "${C[@]}" "${extra[@]}" -o "$TMP/${loss}2.safetensors" --checkpoint "$TMP/$loss.ckpt" \
    >/dev/null 2>&1
  check "layering $loss: resumed bytes equal" \
    cmp -s "$TMP/$loss.safetensors" "$TMP/${loss}2.safetensors"
done
expect_exit 1 "$NBRDF" "${C[@]}" --run "$TMP/a" --loss decoded -o "$TMP/x.safetensors" \
  --checkpoint "$TMP/decoded.ckpt" --batch 5
check "layering: another batch is refused" grep -q "batch = 4, this run has batch = 5" "$TMP/err"
expect_exit 1 "$NBRDF" "${C[@]}" --run "$TMP/a" --loss latent -o "$TMP/x.safetensors" \
  --checkpoint "$TMP/decoded.ckpt"
check "layering: a checkpoint of the other loss is refused" grep -q "format" "$TMP/err"

# sampler
S=(train sampler --run "$TMP/a" --epochs 3)
"$NBRDF" "${S[@]}" -o "$TMP/s.safetensors" >/dev/null 2>&1
expect_exit 1 "$NBRDF" "${S[@]}" -o "$TMP/s2.safetensors" --checkpoint "$TMP/s.ckpt" --stop-at-step 1
"$NBRDF" "${S[@]}" -o "$TMP/s2.safetensors" --checkpoint "$TMP/s.ckpt" >/dev/null 2>&1
check "sampler: resumed bytes equal" cmp -s "$TMP/s.safetensors" "$TMP/s2.safetensors"
expect_exit 2 "$NBRDF" "${S[@]}" -o "$TMP/s3.safetensors" --minutes x
check "a bad --minutes is named" grep -q -- "--minutes 'x'" "$TMP/err"
finish
