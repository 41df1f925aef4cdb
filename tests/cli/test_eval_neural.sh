#!/usr/bin/env bash
# 'nbrdf eval --model neural*' (issue 5's point-query contract) on an untrained
# bundle: the columns of the ground-truth models, a finite f per row, identical
# rows give identical values, warnings for clamped parameters naming the line,
# and errors (no bundle, missing column) with exit 1.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
"$NBRDF" bundle init bundle --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
h='alpha1,eta,alpha2,r0,albedo,sigma_t,theta_i,phi_i,theta_o,phi_o'
printf '%s\n0.1,1.5,0.3,0.9,0.8,1,30,0,30,180\n0.1,1.5,0.3,0.9,0.8,1,30,0,30,180\n0.005,1.5,0.3,0.9,0.8,7,60,0,10,90\n' \
  "$h" >q.csv
"$NBRDF" eval --model neural --bundle bundle <q.csv >out.csv 2>err.txt
check "neural: exit 0" test $? -eq 0
check "neural: header" grep -qx "$h,f" out.csv
check "neural: 3 finite rows" test "$(awk -F, 'NR>1 && $11+0==$11 && $11>=0 {n++} END {print n}' out.csv)" = 3
check "neural: equal rows equal" test "$(sed -n 2p out.csv)" = "$(sed -n 3p out.csv)"
check "neural: clamp warning names the line" \
  grep -Fq "line 4: alpha1: 0.005 outside the model's trained range [0.01, 1] was clamped to 0.01" err.txt
check "neural: sigma_t clamped like a bake" \
  grep -Fq "line 4: sigma_t: 7 outside the model's trained range [0, 5] was clamped to 5" err.txt
check "neural: untrained warning" grep -q "untrained" err.txt
printf 'alpha,r0,theta_i,phi_i,theta_o,phi_o\n0.5,1,0,0,0,0\n' >c.csv
expect_output '^0\.5,1,0,0,0,0,[0-9.e+-]+$' sh -c "\"$NBRDF\" eval --model neural-conductor --bundle bundle <c.csv"
printf 'alpha,eta,theta_i,phi_i,theta_o,phi_o\n0.2,1.4,20,0,20,180\n' >d.csv
expect_output '^0\.2,1\.4,20,0,20,180,[0-9.e+-]+$' sh -c "\"$NBRDF\" eval --model neural-dielectric --bundle bundle <d.csv"
expect_exit 1 sh -c "\"$NBRDF\" eval --model neural --bundle nowhere <q.csv"
expect_stderr "nowhere" sh -c "\"$NBRDF\" eval --model neural --bundle nowhere <q.csv"
expect_exit 1 sh -c "\"$NBRDF\" eval --model neural --bundle bundle <c.csv"
expect_stderr "missing column 'alpha1' (model neural needs alpha1,eta,alpha2,r0,albedo,sigma_t and the angles)" \
  sh -c "\"$NBRDF\" eval --model neural --bundle bundle <c.csv"
expect_stderr "missing column 'eta' (model neural-dielectric needs alpha,eta and the angles)" \
  sh -c "\"$NBRDF\" eval --model neural-dielectric --bundle bundle <c.csv"
expect_stderr "missing column 'r0' (model neural-conductor needs alpha,r0 and the angles)" \
  sh -c "\"$NBRDF\" eval --model neural-conductor --bundle bundle <d.csv"
expect_stderr "missing column 'alpha1' (model layered needs alpha1,eta,alpha2,r0,albedo,sigma_t and the angles)" \
  sh -c "\"$NBRDF\" eval --model layered <c.csv"
# What a bake refuses, eval refuses, naming the line and column.
printf '%s\n0.1,-1,0.3,0.9,0.8,1,30,0,30,180\n' "$h" >neg.csv
expect_exit 1 sh -c "\"$NBRDF\" eval --model neural --bundle bundle <neg.csv"
expect_stderr "line 2, column 'eta' = -1 is not a finite value >= 0" \
  sh -c "\"$NBRDF\" eval --model neural --bundle bundle <neg.csv"
expect_exit 1 sh -c "\"$NBRDF\" eval --model neural --bundle bundle --range refuse <q.csv"
expect_stderr "line 4, column 'alpha1' = 0.005 is outside the model's trained range [0.01, 1]" \
  sh -c "\"$NBRDF\" eval --model neural --bundle bundle --range refuse <q.csv"
expect_exit 2 sh -c "\"$NBRDF\" eval --model layered --roughness perceptual <q.csv"
finish
