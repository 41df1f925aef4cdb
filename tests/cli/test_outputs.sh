#!/usr/bin/env bash
# Outputs and signals (issue 15, docs/RELIABILITY.md): no writing command
# overwrites one of its inputs (maps, textures, the bundle's files, data,
# checkpoints, env maps; through symlinks, '../' and hard links); special and
# read-only outputs are refused; a replaced file keeps its mode; SIGTERM,
# SIGHUP and SIGKILL during a bake, and a write over `ulimit -f`, leave no file.
# Runs as root in CI: /dev/null is only ever named after a symlink to it was
# refused (a rename replaces a symlink, never its target).
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
"$NBRDF" bundle init b --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
oiiotool --pattern fill:left=0.1:right=0.6 16x16 1 -d uint8 -o alpha1.png
oiiotool --pattern constant:color=0.5,0.5,0.5 8x4 3 -d float -o env.exr
cp -r b b.orig
cp alpha1.png alpha1.orig
base=(--bundle b --alpha1 alpha1.png --eta 1.5 --alpha2 0.3 --r0 0.9 --albedo 0.7 --sigma-t 2)
"$NBRDF" bake "${base[@]}" -o lat.exr >/dev/null 2>&1 || { echo "bake failed" >&2; exit 1; }
cp lat.exr lat.orig

# inputs_intact: the bundle, the map and the texture are byte for byte what they were.
inputs_intact() {
  diff -r b b.orig >/dev/null && cmp -s alpha1.png alpha1.orig && cmp -s lat.exr lat.orig
}
# refused WHAT OUTPUT CMD...: exit 1, the message names OUTPUT, every input untouched.
refused() {
  local what=$1 output=$2; shift 2
  expect_exit 1 "$@"
  check "$what: message names '$output': $(head -c 300 "$TMP/err")" grep -Fq -- "$output" "$TMP/err"
  check "$what: inputs untouched" inputs_intact
}

ln -s alpha1.png sym.png
ln alpha1.png hard.png
ln -s b/decoder.safetensors weights-link
mkdir sub

# bake: the bundle's files and the maps, directly and through links.
refused "bake -o bundle weights" b/decoder.safetensors \
  "$NBRDF" bake "${base[@]}" -o b/decoder.safetensors
refused "bake -o model.json" b/model.json "$NBRDF" bake "${base[@]}" -o b/model.json
# The card is not read but belongs to the bundle (issue 30, 4.5).
refused "bake -o MODEL_CARD.md" b/MODEL_CARD.md "$NBRDF" bake "${base[@]}" -o b/MODEL_CARD.md
refused "bake -o tables via ../" sub/../b/base_tables.safetensors \
  "$NBRDF" bake "${base[@]}" -o sub/../b/base_tables.safetensors
refused "bake -o symlink to weights" weights-link "$NBRDF" bake "${base[@]}" -o weights-link
refused "bake -o map" alpha1.png "$NBRDF" bake "${base[@]}" -o alpha1.png
refused "bake -o symlink to map" sym.png "$NBRDF" bake "${base[@]}" -o sym.png
refused "bake -o hard link to map" hard.png "$NBRDF" bake "${base[@]}" -o hard.png
check "refusal names the input" grep -Fq "alpha1.png" "$TMP/err"

# verify: --json and --heatmap against the texture, a map, the bundle.
vbase=(lat.exr "${base[@]}")
refused "verify --heatmap texture" lat.exr "$NBRDF" verify "${vbase[@]}" --heatmap lat.exr
refused "verify --json texture" lat.exr "$NBRDF" verify "${vbase[@]}" --json lat.exr
refused "verify --json map" hard.png "$NBRDF" verify "${vbase[@]}" --json hard.png
refused "verify --heatmap model.json" b/model.json \
  "$NBRDF" verify "${vbase[@]}" --heatmap b/model.json
refused "verify --json weights" weights-link "$NBRDF" verify "${vbase[@]}" --json weights-link
refused "verify --json MODEL_CARD.md" b/MODEL_CARD.md \
  "$NBRDF" verify "${vbase[@]}" --json b/MODEL_CARD.md

# render: -o / --png against the texture, the env map, the bundle.
rbase=(lat.exr --bundle b --width 8 --height 8 --spp 1)
refused "render -o texture" lat.exr "$NBRDF" render "${rbase[@]}" -o lat.exr
refused "render --png texture" lat.exr "$NBRDF" render "${rbase[@]}" -o r.exr --png lat.exr
refused "render -o env" env.exr "$NBRDF" render "${rbase[@]}" --env env.exr -o env.exr
refused "render -o weights" b/sampler.safetensors \
  "$NBRDF" render "${rbase[@]}" -o b/sampler.safetensors
check "render wrote nothing" test ! -e r.exr

# evaluate: --json against the bundle.
refused "evaluate --json model.json" b/model.json \
  "$NBRDF" evaluate --bundle b --sets rep --count 1 --json b/model.json

# train: data, decoder, tables, checkpoints, bundle files.
echo data >d.nbds
mkdir run
ln d.nbds run/log.csv
refused "train decoder: log.csv is the data" run/log.csv \
  "$NBRDF" train decoder --data d.nbds --run run --steps 1
cp b/decoder.safetensors dec.safetensors
refused "train tables -o decoder" dec.safetensors \
  "$NBRDF" train tables --decoder dec.safetensors -o dec.safetensors
refused "train layering -o tables" b/base_tables.safetensors \
  "$NBRDF" train layering --data d.nbds --run run --tables b/base_tables.safetensors \
  -o b/base_tables.safetensors
refused "train layering --log data" d.nbds \
  "$NBRDF" train layering --data d.nbds --run run --tables b/base_tables.safetensors \
  -o lay.safetensors --log d.nbds
echo x >run/checkpoint.safetensors
refused "train sampler -o checkpoint" run/checkpoint.safetensors \
  "$NBRDF" train sampler --run run -o run/checkpoint.safetensors
refused "train bundle over its own inputs" b/decoder.safetensors \
  "$NBRDF" train bundle -o b --decoder b/decoder.safetensors --tables b/base_tables.safetensors \
  --layering b/layering.safetensors

# Special files: a FIFO, and a symlink to the character device /dev/null.
mkfifo fifo
ln -s /dev/null null-link
refused "bake -o FIFO" fifo "$NBRDF" bake "${base[@]}" -o fifo
check "FIFO still a FIFO" test -p fifo
refused "bake -o symlink to /dev/null" null-link "$NBRDF" bake "${base[@]}" -o null-link
check "null-link still a symlink" test -L null-link
check "/dev/null still a character device" test -c /dev/null
if [ -L null-link ] && grep -Fq "not a regular file" "$TMP/err"; then
  refused "bake -o /dev/null" /dev/null "$NBRDF" bake "${base[@]}" -o /dev/null
  check "/dev/null still a character device" test -c /dev/null
fi
refused "render -o FIFO" fifo "$NBRDF" render "${rbase[@]}" -o fifo
refused "render --png symlink to /dev/null" null-link \
  "$NBRDF" render "${rbase[@]}" -o r.exr --png null-link
refused "verify --json FIFO" fifo "$NBRDF" verify "${vbase[@]}" --json fifo
refused "dataset --out FIFO" fifo "$NBRDF" dataset --out fifo --kind single --count 1 --seed 1
check "FIFO still a FIFO" test -p fifo

# Read-only outputs are refused (mode bits checked: root ignores them), writable ones keep
# their mode.
echo keep >ro.exr
chmod 0444 ro.exr
refused "bake -o read-only" ro.exr "$NBRDF" bake "${base[@]}" -o ro.exr
check "read-only file kept" grep -q keep ro.exr
check "read-only mode kept" test "$(stat -c %a ro.exr)" = 444
check "message says read-only" grep -Fq "read-only" "$TMP/err"
chmod 0444 b/layering.safetensors
cp -r b b.orig2
expect_exit 1 "$NBRDF" bundle init b --seed 5 --force
check "bundle init: refused before any file changed" diff -r b b.orig2
chmod 0644 b/layering.safetensors
echo old >mode.exr
chmod 0640 mode.exr
expect_exit 0 "$NBRDF" bake "${base[@]}" -o mode.exr
check "replaced file keeps mode 640" test "$(stat -c %a mode.exr)" = 640

# Signals during a bake of a 1024x1024 map (several seconds): nothing is left.
oiiotool --pattern constant:color=0.3 1024x1024 1 -d uint8 -o big.png
mkdir sig
big=(--bundle "$TMP/b" --alpha1 "$TMP/big.png" --eta 1.5 --alpha2 0.3 --r0 0.9 --albedo 0.7
  --sigma-t 2 --progress=json)
# bake_signalled SIGNAL [ENV...]: starts a bake in sig/, sends SIGNAL once it has
# written rows, prints its exit status.
bake_signalled() {
  local sig=$1; shift
  rm -f progress.txt # the last run's lines must not count
  (cd sig && exec env "$@" "$NBRDF" bake "${big[@]}" -o big.exr >../progress.txt 2>../sig.err) &
  local pid=$! waited=0
  while ! grep -q '"done":[1-9]' progress.txt 2>/dev/null && [ $waited -lt 600 ]; do
    sleep 0.1
    waited=$((waited + 1))
  done
  kill -s "$sig" $pid
  wait $pid
  echo $?
}
for sig in TERM HUP INT; do
  status=$(bake_signalled $sig)
  check "SIG$sig: exit 1, got $status" test "$status" = 1
  check "SIG$sig: nothing left: $(ls -A sig)" test -z "$(ls -A sig)"
  check "SIG$sig: message" grep -Fq "cancelled; no file written" sig.err
done
status=$(bake_signalled KILL)
check "SIGKILL: killed ($status)" test "$status" = 137
check "SIGKILL: nothing left: $(ls -A sig)" test -z "$(ls -A sig)"
# Without O_TMPFILE (forced): the killed bake leaves its named temporary file; the next
# output into the folder, from a later process, removes it.
status=$(bake_signalled KILL NBRDF_OUTPUT_NAMED_TEMP=1)
check "SIGKILL, named: the temporary file is left: $(ls -A sig)" \
  test "$(ls -A sig | grep -Ec '^\.big\.exr\.[0-9a-f]{8}\.tmp$')" = 1
sleep 2.2 # older than the next process by the 2 s margin (output_file.c)
expect_exit 0 env NBRDF_OUTPUT_NAMED_TEMP=1 "$NBRDF" bake "${base[@]}" -o sig/small.exr
check "stale temporary file removed: $(ls -A sig)" test "$(ls -A sig)" = small.exr
rm -f sig/small.exr

# A file size limit: the write fails with a message naming the file; nothing is left.
for named in 0 1; do
  (cd sig && ulimit -f 64 && exec env NBRDF_OUTPUT_NAMED_TEMP=$named "$NBRDF" bake \
    "${big[@]}" -o big.exr >/dev/null 2>../sig.err)
  status=$?
  check "ulimit -f (named=$named): exit 1, got $status" test "$status" = 1
  check "ulimit -f (named=$named): names the file: $(cat sig.err)" \
    grep -Fq "big.exr: write failed: File too large" sig.err
  check "ulimit -f (named=$named): nothing left: $(ls -A sig)" test -z "$(ls -A sig)"
done

finish
