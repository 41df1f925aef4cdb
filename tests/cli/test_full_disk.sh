#!/usr/bin/env bash
# Outputs whole or absent on a full disk (issue 30, part 4): every writer — the latent
# EXR (bake), the render's EXR and PNG, verify's JSON and heat-map PNG, safetensors
# (bundle init, train tables), a training run's checkpoint and log.csv — run into a
# 700 KB tmpfs filled up to a few bytes: exit 1, a message naming the file and
# "No space left on device", and nothing left in the folder (no partial file, no
# temporary file). A multi-output command writes all or none (render's EXR fits, its
# PNG does not: no EXR). Needs root (mount); prints SKIP and passes otherwise.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
if [ "$(id -u)" != 0 ] || ! command -v mount >/dev/null; then
  echo "SKIP: needs root to mount a tmpfs"
  exit 0
fi
cd "$TMP"
mkdir tfs
if ! mount -t tmpfs -o size=700k tmpfs tfs 2>"$TMP/mount.err"; then
  echo "SKIP: cannot mount a tmpfs: $(cat "$TMP/mount.err")"
  exit 0
fi
trap 'umount "$TMP/tfs" 2>/dev/null; rm -rf "$TMP"' EXIT
bundle="$NBRDF_SOURCE_DIR/models/default"
mkdir tfs/out

# fill KEEP: leaves about KEEP bytes free on the tmpfs (its own file, outside out/).
fill() {
  rm -f tfs/filler
  # Never fill anything but our own small tmpfs (were it unmounted under us, the folder
  # would be on the real disk).
  if [ "$(stat -f -c %T tfs)" != tmpfs ] || [ "$(df --output=size -k tfs | tail -1)" -gt 1024 ]; then
    echo "FAIL: tfs is no longer the 700 KB tmpfs; stopping" >&2
    exit 1
  fi
  local avail
  avail=$(df --output=avail -B1 tfs | tail -1)
  fallocate -l $((avail - $1)) tfs/filler 2>/dev/null ||
    head -c $((avail - $1)) /dev/zero >tfs/filler 2>/dev/null
}

# full WHAT KEEP FILE CMD...: with KEEP bytes free, CMD exits 1 naming FILE and ENOSPC,
# and no file is left under out/.
full() {
  local what=$1 keep=$2 file=$3; shift 3
  rm -rf tfs/out && mkdir tfs/out
  fill "$keep"
  expect_exit 1 "$@"
  check "$what (free $keep): message names $file and ENOSPC: $(head -c 300 "$TMP/err")" \
    grep -Eq "$file.*No space left on device" "$TMP/err"
  # A folder the command made may stay, empty: no file in it, partial or temporary.
  check "$what (free $keep): nothing left: $(find tfs/out -type f | head -5)" \
    test -z "$(find tfs/out -type f)"
}

# Inputs, outside the tmpfs: a 32x32 all-distinct texture (81 KB) and its map.
oiiotool --pattern noise:type=uniform:min=0.05:max=0.9 32x32 1 -d float -o a1.exr
params=(--alpha1 a1.exr --eta 1.5 --alpha2 0.3 --r0 0.8 --albedo 0.7 --sigma-t 2)
"$NBRDF" bake --bundle "$bundle" "${params[@]}" -o lat.exr >/dev/null ||
  { echo "FAIL: bake of the input texture" >&2; exit 1; }
"$NBRDF" dataset --out data.nbds --kind single --count 8 --seed 1 >/dev/null 2>&1 ||
  { echo "FAIL: dataset" >&2; exit 1; }

for keep in 0 16384; do
  full "bake" $keep out/lat.exr "$NBRDF" bake --bundle "$bundle" "${params[@]}" -o tfs/out/lat.exr
  full "render -o" $keep out/r.exr "$NBRDF" render lat.exr --bundle "$bundle" -o tfs/out/r.exr \
    --width 64 --height 64 --spp 1
  full "bundle init" $keep out/b/ "$NBRDF" bundle init tfs/out/b --seed 1
  full "train tables" $keep out/t.safetensors "$NBRDF" train tables \
    --decoder "$bundle/decoder.safetensors" -o tfs/out/t.safetensors --steps 1
done
# The JSON and the heat-map are small (3 KB, 1 KB): a full disk.
full "verify --json" 0 out/v.json "$NBRDF" verify lat.exr --bundle "$bundle" "${params[@]}" \
  --texels 1 --spp 16 --json tfs/out/v.json
full "verify --heatmap" 0 out/h.png "$NBRDF" verify lat.exr --bundle "$bundle" "${params[@]}" \
  --texels 1 --spp 16 --heatmap tfs/out/h.png
# The 64x64 render's EXR (42 KB) fits, its PNG (8 KB) does not: neither is left.
full "render --png" 45056 out/r.png "$NBRDF" render lat.exr --bundle "$bundle" \
  -o tfs/out/r.exr --png tfs/out/r.png --width 64 --height 64 --spp 1
# verify's JSON (3 KB) fits, its heat-map does not.
full "verify --json --heatmap" 4096 out/h.png "$NBRDF" verify lat.exr --bundle "$bundle" \
  "${params[@]}" --texels 1 --spp 16 --json tfs/out/v.json --heatmap tfs/out/h.png
# A training run's checkpoint (safetensors) and log.csv.
full "train decoder run" 0 out/run/ "$NBRDF" train decoder --data data.nbds --run tfs/out/run \
  --steps 2

rm -f tfs/filler
finish
