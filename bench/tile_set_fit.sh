#!/usr/bin/env bash
# One fit for a whole tile set (docs/FARM.md, "One fit per set: measured"):
#  1. a 10-tile set of 256² tiles at --accuracy specialised: `nbrdf fit` over the set once,
#     then `nbrdf bake --fit` of the set; times, and the decoder checksum of every tile;
#  2. seams: two 256² tiles cut from one continuous 512 x 256 set of maps, baked with one
#     shared fit and with a fit per tile (and at fast); the lobes decoded at the texels on both
#     sides of the border (column 255 of tile 1001, column 0 of tile 1002, 16 rows, 64
#     direction pairs), their relative L1 difference per row pair (the lobe-error measure of
#     docs/METRICS.md, one side as reference), median and worst.
#
#   bench/tile_set_fit.sh [BUILD_DIR] [WORK_DIR]
# Environment: BUDGET (the seam fits' budget, 60), PARTS ("ten seams").
set -euo pipefail
source "$(dirname "$0")/bench_dirs.sh" "$@"
budget=${BUDGET:-60}
parts=${PARTS:-ten seams}
cd "$work"
export OPENBLAS_NUM_THREADS=1
t() { /usr/bin/time -f "%e %U" -o "$1.time" "${@:2}" >"$1.log" 2>&1; cat "$1.time"; }

[ -d src ] || bash "$root/examples/make_maps.sh" src >/dev/null
# 1. Ten tiles: the example maps, alpha1 and r0 shifted per tile.
ten() {
mkdir -p ten out10
for i in 0 1 2 3 4 5 6 7 8 9; do
  tile=$((1001 + i))
  for m in eta.exr alpha2.png albedo.png sigma_t.exr; do cp "src/$m" "ten/${m%%.*}.$tile.${m##*.}"; done
  oiiotool --pattern fill:left=0.0$((i + 1)):right=0.$((i + 3)) 256x256 1 -d uint8 -o "ten/alpha1.$tile.png"
  oiiotool src/r0.png --mulc 0.$((99 - i)) -d uint8 -o "ten/r0.$tile.png"
done
ten=(--alpha1 'ten/alpha1.<UDIM>.png' --eta 'ten/eta.<UDIM>.exr' --alpha2 'ten/alpha2.<UDIM>.png'
  --r0 'ten/r0.<UDIM>.png' --albedo 'ten/albedo.<UDIM>.png' --sigma-t 'ten/sigma_t.<UDIM>.exr')
echo "== 10 tiles of 256², specialised (wall s, CPU s)"
echo "fit:  $(t fit10 "$nbrdf" fit "${ten[@]}" --accuracy specialised -o ten.nbfit)"
echo "bake: $(t bake10 "$nbrdf" bake "${ten[@]}" --fit ten.nbfit -o 'out10/lat.<UDIM>.exr')"
echo "decoder checksums of the 10 tiles (one line = one decoder):"
for f in out10/lat.*.exr; do "$nbrdf" info "$f" | sed -n 's/^decoder: *own ([0-9]* bytes, checksum \([0-9a-f]*\)).*/\1/p'; done |
  sort | uniq -c
}

# 2. Seams: one continuous set of float maps (no 8-bit steps) cut into two tiles.
seams() {
mkdir -p wide cut fast shared pertile
oiiotool --pattern fill:left=0.02:right=0.4 512x256 1 -d float -o wide/alpha1.exr
oiiotool --pattern fill:top=1.2:bottom=1.7 512x256 1 -d float -o wide/eta.exr
oiiotool --pattern fill:left=0.1:right=0.6 512x256 1 -d float -o wide/alpha2.exr
oiiotool --pattern fill:topleft=0.95,0.64,0.54:topright=0.91,0.92,0.92:bottomleft=0.9,0.6,0.3:bottomright=0.6,0.7,0.9 \
  512x256 3 -d float -o wide/r0.exr
oiiotool --pattern noise:type=uniform:min=0.3:max=0.95:seed=3 9x5 3 --resize:filter=cubic 512x256 \
  --clamp:min=0:max=1 -d float -o wide/albedo.exr
oiiotool --pattern fill:left=0:right=3 512x256 1 -d float -o wide/sigma_t.exr
for m in alpha1.exr eta.exr alpha2.exr r0.exr albedo.exr sigma_t.exr; do
  oiiotool "wide/$m" --cut 256x256+0+0 -o "cut/${m%%.*}.1001.${m##*.}"
  oiiotool "wide/$m" --cut 256x256+256+0 -o "cut/${m%%.*}.1002.${m##*.}"
done
cut=(--alpha1 'cut/alpha1.<UDIM>.exr' --eta 'cut/eta.<UDIM>.exr' --alpha2 'cut/alpha2.<UDIM>.exr'
  --r0 'cut/r0.<UDIM>.exr' --albedo 'cut/albedo.<UDIM>.exr' --sigma-t 'cut/sigma_t.<UDIM>.exr')
echo "== seams: two 256² tiles of one continuous 512x256 set, specialised at budget $budget s"
echo "fast:            $(t seam_fast "$nbrdf" bake "${cut[@]}" -o 'fast/lat.<UDIM>.exr')"
echo "shared fit:      $(t seam_fit "$nbrdf" fit "${cut[@]}" --accuracy specialised --budget "$budget" -o seam.nbfit)"
echo "  bake:          $(t seam_shared "$nbrdf" bake "${cut[@]}" --fit seam.nbfit -o 'shared/lat.<UDIM>.exr')"
echo "a fit per tile:  $(t seam_pertile "$nbrdf" bake "${cut[@]}" --accuracy specialised --budget "$budget" -o 'pertile/lat.<UDIM>.exr')"

python3 - "$nbrdf" <<'PY'
import csv, io, math, subprocess, sys
nbrdf = sys.argv[1]
dirs = []
for ti in (10, 30, 50, 70):
    for pi in (0, 90):
        for to in (10, 40, 70):
            for po in (180, 200, 270):
                dirs.append((ti, pi, to, po))
dirs = dirs[:64]
def decode(tex, u):
    rows = ["u,v,theta_i,phi_i,theta_o,phi_o"]
    for y in range(8, 256, 16):
        v = (y + 0.5) / 256
        for d in dirs:
            rows.append("%r,%r,%g,%g,%g,%g" % ((u, v) + d))
    out = subprocess.run([nbrdf, "eval", "--texture", tex, "--device", "cpu"], input="\n".join(rows) + "\n",
                         capture_output=True, text=True, check=True).stdout
    r = list(csv.DictReader(io.StringIO(out)))
    keys = [k for k in r[0] if k.startswith("f")]
    vals = [sum(float(x[k]) for k in keys) for x in r]
    n = len(dirs)
    return [vals[i * n:(i + 1) * n] for i in range(len(vals) // n)]
def diff(a, b):
    errs = sorted(sum(abs(x - y) for x, y in zip(ra, rb)) / max(1e-12, sum(abs(y) for y in rb))
                  for ra, rb in zip(a, b))
    p = lambda q: errs[min(len(errs) - 1, int(q * len(errs)))]
    return f"{100 * p(0.5):.2f} % / {100 * p(0.9):.2f} % / {100 * errs[-1]:.2f} %"
# Across the border (column 255 of 1001, column 0 of 1002) against a pair of neighbours inside
# one tile (columns 254 and 255 of 1001): the maps change by the same step between them.
print("| textures | across the border: median / p90 / worst | inside tile 1001, same step |")
print("|---|---|---|")
for name in ("fast", "shared", "pertile"):
    a = decode(f"{name}/lat.1001.exr", 255.5 / 256)
    b = decode(f"{name}/lat.1002.exr", 0.5 / 256)
    c = decode(f"{name}/lat.1001.exr", 254.5 / 256)
    print(f"| {name} | {diff(a, b)} | {diff(c, a)} |")
PY
}

for part in $parts; do "$part"; done
