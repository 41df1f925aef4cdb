#!/usr/bin/env bash
# The example maps (make_maps.sh) with the universal path's tails painted in
# (issue 35): a low-IOR top half and a sharp left half, so the four quadrants
# are low-IOR and sharp (top left), low-IOR over the original roughness (top
# right), sharp at the original IOR (bottom left) and the example maps as they
# were (bottom right). Deterministic; oiiotool only.
#   eta.exr     top half: a left-to-right gradient 1.05 .. 1.3; bottom half:
#               make_maps.sh's stripes of 1.3 and 1.7 (float)
#   alpha1.exr  left half: a top-to-bottom gradient 0.01 .. 0.05; right half:
#               make_maps.sh's gradient (0.475 .. 0.9 there). Float: 8 bits
#               would round 0.01 .. 0.05 to five values, some below the
#               trained 0.01
#   the others: make_maps.sh's (alpha1.png is removed: use alpha1.exr)
#   examples/make_sharp_maps.sh [DIR]   (default examples/maps-sharp)
set -euo pipefail
dir=${1:-"$(dirname "$0")/maps-sharp"}
bash "$(dirname "$0")/make_maps.sh" "$dir" >/dev/null
cd "$dir"
n=256 h=128
# --paste: the image below the top of the stack is pasted onto the top one.
oiiotool --pattern fill:left=1.05:right=1.3 ${n}x${h} 1 \
  --pattern checker:width=32:height=$n:color1=1.3:color2=1.7 ${n}x${n} 1 --paste +0+0 -d float -o eta.exr
oiiotool --pattern fill:top=0.01:bottom=0.05 ${h}x${n} 1 \
  --pattern fill:left=0.05:right=0.9 ${n}x${n} 1 --paste +0+0 -d float -o alpha1.exr
rm -f alpha1.png
echo "make_sharp_maps: wrote alpha1.exr eta.exr alpha2.png r0.png albedo.png sigma_t.exr in $dir"
