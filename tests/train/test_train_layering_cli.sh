#!/usr/bin/env bash
# 'nbrdf train layering --loss decoded' as a user runs it: a checkpointed run
# resumed by the same command with more epochs, the latent run's decoded
# figure, and the usage and mismatch errors. (The numerics are checked by
# test_train_layering.c and test_train_layering_grad.c.)
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"

D="$TMP/l2.nbds"
"$NBRDF" dataset --out "$D" --kind layered2 --count 12 --seed 5 --incident 2 --outgoing 8 \
  --spp 16 2>/dev/null
check "dataset" [ $? -eq 0 ]
"$NBRDF" train decoder --data "$D" --run "$TMP/run" --preset small --steps 10 --validation 0 \
  --brdf-weight 0.5 >/dev/null 2>&1
check "decoder run" [ -f "$TMP/run/decoder.safetensors" ]
"$NBRDF" train tables --decoder "$TMP/run/decoder.safetensors" -o "$TMP/t.safetensors" \
  --alpha-nodes 3 --eta-nodes 3 --r0-nodes 3 --eta-warp 2 --r0-warp 2 --steps 5 >/dev/null 2>&1
check "tables (warped axes)" [ -f "$TMP/t.safetensors" ]
expect_exit 2 "$NBRDF" train tables --decoder "$TMP/run/decoder.safetensors" -o "$TMP/t2.safetensors" \
  --eta-warp 9
check "a bad warp is named" grep -q -- "--eta-warp expects a number in \\[0.25, 4\\], got '9'" "$TMP/err"
check "and writes nothing" [ ! -e "$TMP/t2.safetensors" ]

common=(--data "$D" --tables "$TMP/t.safetensors" --batch 4 --rows 8)
"$NBRDF" train layering "${common[@]}" --run "$TMP/run" --epochs 10 -o "$TMP/latent.safetensors" \
  >"$TMP/latent.out" 2>/dev/null
check "latent run exits 0" [ $? -eq 0 ]
check "latent run reports its decoded validation loss" \
  grep -Eq 'decoded validation loss [0-9.e-]+ \(the run.s own latents: [0-9.e-]+\)' "$TMP/latent.out"

dec=(--loss decoded --decoder "$TMP/run/decoder.safetensors" --checkpoint "$TMP/l.ckpt"
  --init "$TMP/latent.safetensors" -o "$TMP/dec.safetensors" --log "$TMP/dec.csv")
"$NBRDF" train layering "${common[@]}" "${dec[@]}" --epochs 3 >"$TMP/a.out" 2>/dev/null
check "decoded run exits 0" [ $? -eq 0 ]
check "decoded run: 3 epochs from scratch" grep -q 'epochs 3 (resumed at 0)' "$TMP/a.out"
"$NBRDF" train layering "${common[@]}" "${dec[@]}" --epochs 5 >"$TMP/b.out" 2>/dev/null
check "the same command with more epochs resumes" grep -q 'epochs 5 (resumed at 3)' "$TMP/b.out"
check "the log holds epochs 1..5 once each" [ "$(cut -d, -f1 "$TMP/dec.csv" | tr '\n' ' ')" = "epoch 1 2 3 4 5 " ]

# The energy penalty (issue 18): on in both trainings, refused with the latent loss, and a bad
# angle list is named.
"$NBRDF" train decoder --data "$D" --run "$TMP/run_e" --preset small --steps 4 --validation 0 \
  --energy 1 --energy-brdfs 4 --energy-angles 60,85,89 >/dev/null 2>&1
check "decoder run with --energy" [ -f "$TMP/run_e/decoder.safetensors" ]
expect_exit 2 "$NBRDF" train decoder --data "$D" --run "$TMP/run_e2" --energy 1 --energy-angles 0,95
check "a bad energy angle is named" grep -q -- "--energy-angles: '95' is not an angle" "$TMP/err"
"$NBRDF" train layering "${common[@]}" --loss decoded --decoder "$TMP/run/decoder.safetensors" \
  --epochs 1 --energy 1 --energy-brdfs 2 -o "$TMP/dec_e.safetensors" >/dev/null 2>&1
check "decoded layering run with --energy" [ -f "$TMP/dec_e.safetensors" ]
expect_exit 2 "$NBRDF" train layering "${common[@]}" --run "$TMP/run" --epochs 1 --energy 1 \
  -o "$TMP/x.safetensors"
check "--energy needs the decoded loss" grep -q -- "--energy needs --loss decoded" "$TMP/err"
"$NBRDF" train tables --decoder "$TMP/run/decoder.safetensors" -o "$TMP/t1.safetensors" \
  --alpha-nodes 2 --eta-nodes 2 --r0-nodes 2 --steps 2 --eta-min 1 >/dev/null 2>&1
check "tables from eta = 1" [ -f "$TMP/t1.safetensors" ]

# The sampler also learns the latents the layering network gives the data (what a bake feeds it).
"$NBRDF" train sampler --run "$TMP/run" -o "$TMP/s.safetensors" --epochs 2 \
  --layering "$TMP/dec.safetensors" --tables "$TMP/t.safetensors" --data "$D" >"$TMP/s.out" 2>/dev/null
check "sampler on run + layered latents" grep -q '24 latents (12 of the run, 12 from the layering network)' "$TMP/s.out"
expect_exit 2 "$NBRDF" train sampler --run "$TMP/run" -o "$TMP/s2.safetensors" --layering "$TMP/dec.safetensors"

expect_exit 1 "$NBRDF" train layering "${common[@]}" "${dec[@]}" --epochs 6 --rows 4
check "another setting is refused, naming the checkpoint" grep -q 'l.ckpt' "$TMP/err"
expect_exit 1 "$NBRDF" train layering "${common[@]}" --loss decoded \
  --decoder "$TMP/run/decoder.safetensors" --init "$TMP/latent.safetensors" --preset paper \
  -o "$TMP/x.safetensors"
check "--init of another preset is refused" grep -q "preset 'small'" "$TMP/err"
expect_exit 2 "$NBRDF" train layering "${common[@]}" --loss kl -o "$TMP/x.safetensors" --run "$TMP/run"
expect_exit 2 "$NBRDF" train layering "${common[@]}" --loss decoded -o "$TMP/x.safetensors"
check "no partial output" [ ! -e "$TMP/x.safetensors" ]
finish
