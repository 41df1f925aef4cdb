#!/usr/bin/env bash
# Writes a small set of 256x256 parameter maps for the bake into DIR (default
# examples/maps), with oiiotool (Debian: openimageio-tools). Deterministic.
#   alpha1.png   top roughness: a left-to-right gradient 0.05 .. 0.9 (8-bit, non-colour)
#   eta.exr      top IOR: vertical stripes of 1.3 and 1.7 (float: 8 bits cannot hold eta)
#   alpha2.png   bottom roughness: a top-to-bottom gradient 0.1 .. 0.6 (8-bit, non-colour)
#   r0.png       bottom Schlick R0: a copper / silver checker (8-bit sRGB colour data)
#   albedo.png   medium albedo: soft painted-looking colour blobs (8-bit sRGB colour data)
#   sigma_t.exr  medium extinction: four vertical steps 0, 1, 2, 5 (float)
# Colour maps are sRGB-encoded like any painted texture; the bake linearises them.
set -euo pipefail
dir=${1:-"$(dirname "$0")/maps"}
mkdir -p "$dir"
cd "$dir"
n=256
oiiotool --pattern fill:left=0.05:right=0.9 ${n}x${n} 1 -d uint8 -o alpha1.png
oiiotool --pattern checker:width=32:height=$n:color1=1.3:color2=1.7 ${n}x${n} 1 -d float -o eta.exr
oiiotool --pattern fill:top=0.1:bottom=0.6 ${n}x${n} 1 -d uint8 -o alpha2.png
oiiotool --pattern checker:width=32:height=32:color1=0.95,0.64,0.54:color2=0.91,0.92,0.92 \
  ${n}x${n} 3 -d uint8 -o r0.png
oiiotool --pattern noise:type=uniform:min=0.2:max=0.95:seed=3 5x5 3 \
  --resize:filter=cubic ${n}x${n} --clamp:min=0:max=1 -d uint8 -o albedo.png
oiiotool --pattern constant:color=0 ${n}x${n} 1 \
  --fill:color=1 64x${n}+64+0 --fill:color=2 64x${n}+128+0 --fill:color=5 64x${n}+192+0 \
  -d float -o sigma_t.exr
echo "make_maps: wrote alpha1.png eta.exr alpha2.png r0.png albedo.png sigma_t.exr in $dir"
