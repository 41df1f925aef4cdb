#!/usr/bin/env bash
# Roughness below the trained range (issue 35 part 6; docs/BAKE.md, "Sharp coats"): constants
# alpha1 in ALPHA1S over a conductor alpha2 in ALPHA2S (eta 1.5, r0 0.9, no slab), each baked
# at fast (which clamps alpha1 to the trained 0.01), fitted and specialised (which fit it as
# given; --no-fallback, so that the level's own texture is verified: the held-out check's
# decision is shown from the same figures), and specialised again with the fine-tune's energy
# term off (--fit-energy 0: what the held-out check's energy guard has to catch). Per row: the
# bake's held-out lobe error against the truth at the user's alpha (fast's on the same tuples
# beside it), fast against the truth of the clamped alpha1 = 0.01 (what it was trained to
# stand for; once per alpha2), the energy guard's largest decoded albedo over the fit's tuples
# (specialised, fast, specialised without the energy term), and `nbrdf verify`'s lobe error
# and largest decoded albedo of each texture against the truth at the user's alpha (SPP walks
# per lobe image). Prints a markdown table on stdout; logs and textures in WORK_DIR.
#
#   bench/sharp_alpha.sh [BUILD_DIR] [WORK_DIR]
# Environment: ALPHA1S ("0.001 0.0025 0.005"), ALPHA2S ("0.05 0.3"), BUDGET_FITTED (120),
# BUDGET_SPECIALISED (300), SPP (1024), SEED (1), ENERGY_OFF (1: the --fit-energy 0 column).
set -euo pipefail
source "$(dirname "$0")/bench_dirs.sh" "$@"
alpha1s=${ALPHA1S:-"0.001 0.0025 0.005"}
alpha2s=${ALPHA2S:-"0.05 0.3"}
bf=${BUDGET_FITTED:-120}
bs=${BUDGET_SPECIALISED:-300}
spp=${SPP:-1024}
seed=${SEED:-1}
energy_off=${ENERGY_OFF:-1}
export OPENBLAS_NUM_THREADS=1 # measured: faster on the loaded 2-core machine (ARCHITECTURE.md)
export NBRDF_BUNDLE=${NBRDF_BUNDLE:-$root/models/default}
common=(--mip-levels 1 --energy-audit 0 --seed "$seed")

# accuracy FILE KEY: a field of the texture's nbrdf:accuracy ("" when absent).
accuracy() {
  "$nbrdf" info "$1" | sed -n 's/^accuracy: *//p' | tr ';' '\n' | sed -n "s/^ *$2=//p" | head -1
}
# verify_field FILE.json KEY: verify's overall lobe error median in percent, or max albedo.
median() {
  python3 -c 'import json,sys; print("%.1f" % json.load(open(sys.argv[1]))["overall"]["lobe_error_median_pct"])' "$1"
}
max_albedo() {
  python3 -c 'import json,sys; print("%.2f" % json.load(open(sys.argv[1]))["max_albedo"])' "$1"
}
pct() { python3 -c 'import sys; print("%.1f" % (100 * float(sys.argv[1])))' "$1"; }
num() { python3 -c 'import sys; print("%.2f" % float(sys.argv[1]))' "$1"; }

echo "| alpha1 | alpha2 | fast held-out (truth at 0.01) | fast held-out (truth at alpha1) | fitted held-out | specialised held-out | guard: max albedo specialised / fast | verify fast | verify fitted | verify specialised | verify max albedo fast / specialised | energy term off: held-out, guard max albedo, verify max albedo | falls back |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for a2 in $alpha2s; do
  # Fast's held-out error on the clamped alpha1's own truth: a fitted bake of 0.01 reports it.
  clamped=(--alpha1 0.01 --eta 1.5 --alpha2 "$a2" --r0 0.9 --albedo 0 --sigma-t 0)
  "$nbrdf" bake "${clamped[@]}" "${common[@]}" --accuracy fitted --budget "$bf" \
    -o "$work/a2_${a2}.clamped.exr" >"$work/a2_${a2}.clamped.log" 2>&1
  fast_clamped=$(accuracy "$work/a2_${a2}.clamped.exr" fastError)
  for a1 in $alpha1s; do
    scene=(--alpha1 "$a1" --eta 1.5 --alpha2 "$a2" --r0 0.9 --albedo 0 --sigma-t 0)
    tag="$work/a1_${a1}_a2_${a2}"
    "$nbrdf" bake "${scene[@]}" "${common[@]}" -o "$tag.fast.exr" >"$tag.fast.log" 2>&1
    levels="fitted specialised"
    [ "$energy_off" = 1 ] && levels="$levels off"
    for level in $levels; do
      case $level in
        fitted) args=(--accuracy fitted --budget "$bf") ;;
        specialised) args=(--accuracy specialised --budget "$bs") ;;
        off) args=(--accuracy specialised --budget "$bs" --fit-energy 0) ;;
      esac
      "$nbrdf" bake "${scene[@]}" "${common[@]}" "${args[@]}" --no-fallback \
        -o "$tag.$level.exr" >"$tag.$level.log" 2>&1
    done
    for level in fast $levels; do
      "$nbrdf" verify "$tag.$level.exr" "${scene[@]}" --spp "$spp" --seed "$seed" \
        --json "$tag.$level.verify.json" >"$tag.$level.verify.txt" 2>&1
    done
    fast_user=$(accuracy "$tag.fitted.exr" fastError)
    fitted=$(accuracy "$tag.fitted.exr" heldoutError)
    fitted_alb=$(accuracy "$tag.fitted.exr" maxAlbedoFit)
    fitted_falb=$(accuracy "$tag.fitted.exr" fastMaxAlbedoFit)
    spec=$(accuracy "$tag.specialised.exr" heldoutError)
    spec_fast=$(accuracy "$tag.specialised.exr" fastError)
    spec_alb=$(accuracy "$tag.specialised.exr" maxAlbedoFit)
    spec_falb=$(accuracy "$tag.specialised.exr" fastMaxAlbedoFit)
    off="-"
    if [ "$energy_off" = 1 ]; then
      off="$(pct "$(accuracy "$tag.off.exr" heldoutError)") %, $(num "$(accuracy "$tag.off.exr" maxAlbedoFit)"), $(max_albedo "$tag.off.verify.json")"
    fi
    # The held-out check's decision from the same figures (bake_fit_worse_than_fast).
    back=$(python3 -c '
import sys
f, ff, fa, ffa, s, sf, sa, sfa = map(float, sys.argv[1:9])
m = 0.0025  # BAKE_FALLBACK_MARGIN
def why(e, b, a, fa):
    r = []
    if e > b + m: r.append("lobe")
    if not a <= max(1.01, fa + 0.03): r.append("energy")  # bake_energy_creates
    return r
out = ["%s (%s)" % (n, ", ".join(w)) for n, w in (("fitted", why(f, ff, fa, ffa)),
       ("specialised", why(s, sf, sa, sfa))) if w]
print("; ".join(out) or "none")' "$fitted" "$fast_user" "$fitted_alb" "$fitted_falb" "$spec" \
      "$spec_fast" "$spec_alb" "$spec_falb")
    echo "| $a1 | $a2 | $(pct "$fast_clamped") % | $(pct "$fast_user") % | $(pct "$fitted") % | $(pct "$spec") % | $(num "$spec_alb") / $(num "$spec_falb") | $(median "$tag.fast.verify.json") % | $(median "$tag.fitted.verify.json") % | $(median "$tag.specialised.verify.json") % | $(max_albedo "$tag.fast.verify.json") / $(max_albedo "$tag.specialised.verify.json") | $off | $back |"
  done
done
