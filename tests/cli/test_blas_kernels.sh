#!/usr/bin/env bash
# The CLI's choice of BLAS kernels: --version reports them; $NBRDF_BLAS_CORETYPE makes the
# CLI re-execute itself once with OpenBLAS's kernels of that name (the mechanism that picks
# the AVX-512 kernels on CPUs OpenBLAS 0.3.21 does not recognise), "keep" keeps OpenBLAS's
# own; kernels the CPU cannot run are refused with a warning; and the networks give the
# same values on other kernels within float rounding.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
unset OPENBLAS_CORETYPE NBRDF_BLAS_CHOSEN NBRDF_BLAS_CORETYPE

expect_output "^BLAS: OpenBLAS .*; kernels [A-Za-z0-9]+( \([^)]*\))?; CPU AVX-512: (yes|no)" \
  "$NBRDF" --version
# OpenBLAS's own choice; the CLI may have re-executed itself with wider kernels.
native=$(env NBRDF_BLAS_CORETYPE=keep "$NBRDF" --version | sed -nE 's/.*; kernels ([A-Za-z0-9]+).*/\1/p')
if env NBRDF_BLAS_CORETYPE=keep "$NBRDF" --version | grep -q "wider kernels available"; then
  wide=$(env NBRDF_BLAS_CORETYPE=keep "$NBRDF" --version | sed -nE 's/.*wider kernels available: ([A-Za-z0-9]+).*/\1/p')
  expect_output "kernels $wide \(chosen by nbrdf: OPENBLAS_CORETYPE=$wide\)" "$NBRDF" --version
fi
check "native kernels named" test -n "$native"
# Sandybridge (AVX) runs on every x86-64 CPU this project builds for (AVX2 is used elsewhere).
other=Sandybridge
[ "$native" = Sandybridge ] && other=Haswell
expect_output "kernels $other \(chosen by nbrdf: OPENBLAS_CORETYPE=$other\)" \
  env NBRDF_BLAS_CORETYPE=$other "$NBRDF" --version
expect_output "kernels $native; " env NBRDF_BLAS_CORETYPE=keep "$NBRDF" --version
expect_output "kernels $other \(OPENBLAS_CORETYPE=$other from the environment\)" \
  env OPENBLAS_CORETYPE=$other "$NBRDF" --version
if "$NBRDF" --version | grep -q "CPU AVX-512: no"; then
  expect_exit 0 env NBRDF_BLAS_CORETYPE=SkylakeX "$NBRDF" --version
  expect_stderr "needs AVX-512, which this CPU lacks" env NBRDF_BLAS_CORETYPE=SkylakeX "$NBRDF" --version
  check "no AVX-512 kernels offered without AVX-512" bash -c "! '$NBRDF' --version | grep -q 'wider kernels available: SkylakeX'"
fi

# The same point queries through the networks on two kernel families.
"$NBRDF" bundle init bundle --seed 5 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
{
  echo 'alpha1,eta,alpha2,r0,albedo,sigma_t,theta_i,phi_i,theta_o,phi_o'
  for t in 0 20 40 60 80; do echo "0.2,1.5,0.3,0.9,0.8,1,$t,0,30,180"; done
} >q.csv
env NBRDF_BLAS_CORETYPE=keep "$NBRDF" eval --model neural --bundle bundle <q.csv >a.csv 2>/dev/null
env NBRDF_BLAS_CORETYPE=$other "$NBRDF" eval --model neural --bundle bundle <q.csv >b.csv 2>/dev/null
check "eval on $other kernels agrees with $native within float rounding" \
  awk -F, 'NR == FNR { a[FNR] = $NF; next }
           FNR > 1 { d = $NF - a[FNR]; if (d < 0) d = -d; s = a[FNR] < 0 ? -a[FNR] : a[FNR];
                     if (d > 1e-4 * (s + 1e-6)) bad++; n++ }
           END { exit !(n == 5 && bad == 0) }' a.csv b.csv
finish
