#!/usr/bin/env bash
# Writes a CSV of point queries tracing the in-plane lobe of one layered BRDF
# (smooth clear coat over brushed-looking gold-ish metal) at θi = 30°:
# θo from -85° to 85° in the incidence plane (negative = φo 180°).
set -euo pipefail
echo "alpha1,eta,alpha2,r0,albedo,sigma_t,theta_i,phi_i,theta_o,phi_o"
for t in $(seq -85 5 85); do
  if [ "$t" -lt 0 ]; then phi=180; to=$(( -t )); else phi=0; to=$t; fi
  echo "0.05,1.5,0.4,0.9,0.8,0.5,30,0,$to,$phi"
done
