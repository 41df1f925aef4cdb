#!/usr/bin/env bash
# 'nbrdf dataset': generation with JSON progress, resume of a cut file,
# --check on a good and a corrupted file, a usage error. Each CLI start costs
# ~0.5 s (more under sanitizers), so the library tests (test_dataset.c) cover
# the rest: thread independence, cancellation, mismatched settings.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"

F="$TMP/d.nbds"
ARGS=(--kind layered3 --count 3 --seed 5 --incident 2 --outgoing 8 --spp 16)
# (Not through expect_stderr: grep -q would end the pipe, and SIGPIPE the run.)
"$NBRDF" dataset --out "$F" "${ARGS[@]}" --progress=json >"$TMP/progress"
check "dataset exits 0" [ $? -eq 0 ]
check "JSON progress on stdout, the format of every command" \
  grep -Eq '^\{"event":"progress","stage":"dataset","done":3,"total":3,"seconds":[0-9.]+,"rate":' "$TMP/progress"

"$NBRDF" dataset --check "$F" >"$TMP/sum" 2>&1
check "--check passes on a fresh file" [ $? -eq 0 ]
check "--check counts 3 three-layer BRDFs" grep -q '^layered3: 3$' "$TMP/sum"
check "--check counts 48 samples" grep -q '^samples: 48$' "$TMP/sum"

# A cut file resumes to the identical file.
size=$(stat -c %s "$F")
head -c $((size - 100)) "$F" >"$TMP/cut.nbds"
"$NBRDF" dataset --out "$TMP/cut.nbds" "${ARGS[@]}" 2>"$TMP/err"
check "the cut file resumes after 2 records" grep -qF '(2 resumed)' "$TMP/err"
check "resumed file is identical" cmp -s "$F" "$TMP/cut.nbds"

# One flipped byte in a sample value is refused, naming the record.
cp "$F" "$TMP/bad.nbds"
printf '\x7f' | dd of="$TMP/bad.nbds" bs=1 seek=400 conv=notrunc status=none
"$NBRDF" dataset --check "$TMP/bad.nbds" >/dev/null 2>"$TMP/err"
check "--check exits 1 on a corrupted file" [ $? -eq 1 ]
check "--check names record 0" grep -q 'record 0' "$TMP/err"

expect_exit 2 "$NBRDF" dataset --out "$F" --kind layered4 --count 3 --seed 5
finish
