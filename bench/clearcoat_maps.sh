#!/usr/bin/env bash
# The maps of issue 33's clearcoat (bench/audit_cost.sh, bench/audit_head.sh): a gradient
# with noise, every texel its own roughness / colour, as a painted map has.
#   bench/clearcoat_maps.sh SIZE DIR   -> DIR/rough.png (1 channel), DIR/base.png (RGB)
set -eu
size=$1 dir=$2
oiiotool --pattern fill:topleft=0.15:topright=0.85:bottomleft=0.25:bottomright=0.6 \
  "${size}x${size}" 1 --pattern noise:type=uniform:min=-0.05:max=0.05:seed=1 \
  "${size}x${size}" 1 --add -d uint8 -o "$dir/rough.png"
oiiotool --pattern fill:topleft=0.95,0.64,0.54:topright=0.56,0.57,0.58:bottomleft=1.0,0.86,0.57:bottomright=0.91,0.92,0.92 \
  "${size}x${size}" 3 --pattern noise:type=uniform:min=-0.04:max=0.04:seed=2 \
  "${size}x${size}" 3 --add -d uint8 -o "$dir/base.png"
