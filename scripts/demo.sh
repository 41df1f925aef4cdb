#!/usr/bin/env bash
# The README's first command: builds nbrdf and runs its main job on bundled data.
# (Until the bake lands, the main job is a ground-truth lobe of a layered BRDF.)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh build >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
bash examples/make_lobe_queries.sh > "$out/queries.csv"
echo "Layered BRDF (α1=0.05, η=1.5, α2=0.4, R0=0.9, A=0.8, σT=0.5), θi=30°, in-plane lobe:"
./build/nbrdf eval --model layered --spp 4096 --seed 1 < "$out/queries.csv" \
  | awk -F, 'NR==1 {for (i=1;i<=NF;i++) col[$i]=i; print "theta_o  phi_o        f   f_stderr"; next}
             {printf "%7s  %5s  %9.4f  %8.4f\n", $col["theta_o"], $col["phi_o"], $col["f"], $col["f_stderr"]}'
