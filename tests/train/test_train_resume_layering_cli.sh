#!/usr/bin/env bash
# test_train_resume_cli.sh's checks for `train layering` (both losses) and
# `train sampler`: stopped with --stop-at-step (inside an epoch) and resumed by
# the same command, each ends with the bytes of a run that never stopped.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
export OPENBLAS_NUM_THREADS=1

D="$TMP/l2.nbds"
"$NBRDF" dataset --out "$D" --kind layered2 --count 12 --seed 5 --incident 2 --outgoing 8 \
  --spp 16 2>/dev/null
check "dataset" [ $? -eq 0 ]

# a decoder run and tables to train from
"$NBRDF" train decoder --data "$D" --preset small --steps 20 --validation 0 --run "$TMP/a" \
  >/dev/null 2>&1
"$NBRDF" train tables --decoder "$TMP/a/decoder.safetensors" --alpha-nodes 3 --eta-nodes 3 \
  --r0-nodes 3 --steps 9 -o "$TMP/t.safetensors" >/dev/null 2>&1
check "decoder run and tables" [ -f "$TMP/t.safetensors" ]

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
finish
