#!/usr/bin/env bash
# The README's first command: builds nbrdf and runs its main job on the bundled
# example data — bake six layered parameter maps into a latent texture, then
# describe it, verify sampled texels against the Monte Carlo ground truth
# (`nbrdf verify`) — plus a ground-truth lobe of one layered BRDF through
# `nbrdf eval`. The bake uses models/default (a bundle made on the spot by
# `nbrdf bundle init`, untrained and saying so, where that folder is missing).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh build >/dev/null
nbrdf=./build/nbrdf
out=${NBRDF_DEMO_OUT:-build/demo}
mkdir -p "$out"

bash examples/make_maps.sh "$out/maps"
bundle=models/default
if [ ! -f "$bundle/model.json" ]; then
  bundle="$out/untrained-bundle"
  [ -f "$bundle/model.json" ] || "$nbrdf" bundle init "$bundle" --seed 1 >/dev/null
fi
m="$out/maps"
params=(--alpha1 "$m/alpha1.png" --eta "$m/eta.exr" --alpha2 "$m/alpha2.png"
  --r0 "$m/r0.png" --albedo "$m/albedo.png" --sigma-t "$m/sigma_t.exr" --bundle "$bundle")
"$nbrdf" bake "${params[@]}" -o "$out/latent.exr"
"$nbrdf" info "$out/latent.exr"

echo
echo "Verification: 8 stratified texels of level 0, decoded vs the Monte Carlo ground truth:"
"$nbrdf" verify "$out/latent.exr" "${params[@]}" --texels 8 --json "$out/verify.json" \
  --heatmap "$out/verify.png"

echo
bash examples/make_lobe_queries.sh > "$out/queries.csv"
echo "Ground truth: layered BRDF (α1=0.05, η=1.5, α2=0.4, R0=0.9, A=0.8, σT=0.5), θi=30°, in-plane:"
"$nbrdf" eval --model layered --spp 4096 --seed 1 < "$out/queries.csv" \
  | awk -F, 'NR==1 {for (i=1;i<=NF;i++) col[$i]=i; print "theta_o  phi_o        f   f_stderr"; next}
             {printf "%7s  %5s  %9.4f  %8.4f\n", $col["theta_o"], $col["phi_o"], $col["f"], $col["f_stderr"]}'
echo
echo "demo: latent texture in $out/latent.exr; verification in $out/verify.json, $out/verify.png"
