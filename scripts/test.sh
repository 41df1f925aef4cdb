#!/usr/bin/env bash
# Builds nbrdf twice — optimised, and with AddressSanitizer + UBSan — and runs the
# whole test suite on both; then runs the optimised suite a second time on another set of
# OpenBLAS kernels. Prints the kernels at the top of each suite, ctest's summary for each
# and a combined "N passed, N failed" line last. Exit status 0 only if every test passed.
#
# Why a second kernel set: OpenBLAS's result for one row of a GEMM can depend on how many
# rows share the call, differently for each kernel family, so a test asserting more than
# the code promises (docs/ARCHITECTURE.md, "Determinism") passes on the machine it was
# written on and fails on the next. The first pass keeps an OPENBLAS_CORETYPE set in the
# environment (else OpenBLAS's own choice); the second runs on a family whose row handling
# differs from the first's: AVX-512 (SkylakeX, Cooperlake, ...) -> Haswell; Haswell or Zen
# -> SkylakeX where the CPU has AVX-512, else Sandybridge; anything else -> Haswell, then
# Sandybridge, then Prescott, the first the CPU runs that differs from the first pass.
# NBRDF_SKIP_SANITIZE=1 skips the sanitizer build, NBRDF_SKIP_SECOND_BLAS=1 the second pass.
set -uo pipefail
cd "$(dirname "$0")/.."

passed=0
failed=0

# The kernels the library's tests run on (OpenBLAS's choice, or OPENBLAS_CORETYPE's), and
# the CLI's line when it differs: without OPENBLAS_CORETYPE the CLI re-executes itself with
# wider kernels where the CPU has them (src/cli/cli_blas.c).
print_kernels() { # print_kernels BUILD_DIR LABEL
  local lib cli
  lib=$(env "${run_env[@]}" NBRDF_BLAS_CORETYPE=keep "$1/nbrdf" --version 2>&1 | grep '^BLAS:')
  cli=$(env "${run_env[@]}" "$1/nbrdf" --version 2>&1 | grep '^BLAS:')
  echo "== $2: $lib"
  [ "$cli" = "$lib" ] || echo "== $2: the CLI's own: $cli"
}

# The name of the kernels in a BLAS line ("...; kernels Haswell (...); ...").
kernels_of() { sed -nE 's/.*; kernels ([A-Za-z0-9]+).*/\1/p' <<<"$1"; }

cpu_has() { grep -qw "$1" /proc/cpuinfo 2>/dev/null; }

# A kernel family the CPU runs whose results for a row differ from `first`'s; empty if none.
second_coretype() { # second_coretype FIRST
  local first=${1,,} c
  local -a order
  case $first in
    skylakex | cooperlake | sapphirerapids) order=(Haswell Sandybridge Prescott) ;;
    haswell | zen)
      if cpu_has avx512f && cpu_has avx512bw && cpu_has avx512dq && cpu_has avx512vl; then
        order=(SkylakeX Sandybridge Prescott)
      else
        order=(Sandybridge Prescott)
      fi ;;
    *) order=(Haswell Sandybridge Prescott) ;;
  esac
  for c in "${order[@]}"; do
    [ "${c,,}" = "$first" ] && continue
    case $c in
      Haswell) cpu_has avx2 && cpu_has fma || continue ;;
      Sandybridge) cpu_has avx || continue ;;
    esac
    echo "$c"
    return
  done
}

# run_tests BUILD_DIR LABEL LOG: ctest over the built tree, its counts added to the totals.
run_tests() {
  local dir=$1 label=$2 log=$3 start
  print_kernels "$dir" "$label"
  echo "== $label: tests"
  start=$(date +%s)
  (cd "$dir" && env "${run_env[@]}" ctest --output-on-failure --timeout 900 -j "$(nproc)") 2>&1 | tee "$log"
  echo "== $label: $(($(date +%s) - start)) s"
  local line total fails
  line=$(grep -E "tests passed, [0-9]+ tests? failed out of [0-9]+" "$log" | tail -1)
  if [ -z "$line" ]; then
    echo "== $label: ctest printed no summary"
    failed=$((failed + 1))
    return
  fi
  fails=$(sed -E 's/.*passed, ([0-9]+) tests? failed out of ([0-9]+).*/\1/' <<<"$line")
  total=$(sed -E 's/.*failed out of ([0-9]+).*/\1/' <<<"$line")
  passed=$((passed + total - fails))
  failed=$((failed + fails))
}

run_suite() { # run_suite BUILD_DIR LABEL CMAKE_ARGS...
  local dir=$1 label=$2; shift 2
  echo "== $label: build ($dir)"
  if ! bash scripts/build.sh "$dir" "$@"; then
    echo "== $label: build failed"
    failed=$((failed + 1))
    return 1
  fi
  run_tests "$dir" "$label" "$dir/ctest.log"
}

run_env=() # env(1) arguments for the tests and the kernels printed
release_built=0
run_suite build "release" && release_built=1
if [ "${NBRDF_SKIP_SANITIZE:-0}" != 1 ]; then
  # Leak checks stay on; OpenMP's runtime keeps thread pools alive until exit, which
  # LeakSanitizer does not count as a leak. The Vulkan driver allocates once for the process
  # when a GPU is looked for: the CLI's tests run on the CPU device here (NBRDF_DEVICE=cpu;
  # the release suites cover --device auto), and the two tests that open a device check no
  # leaks (tests/CMakeLists.txt); tests/lsan.supp names the driver's allocations.
  NBRDF_DEVICE=cpu ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0" \
    run_suite build-sanitize "asan+ubsan" -DNBRDF_SANITIZE=ON -DNBRDF_BUILD_BENCH=OFF
fi
if [ "$release_built" = 1 ] && [ "${NBRDF_SKIP_SECOND_BLAS:-0}" != 1 ]; then
  first=$(kernels_of "$(NBRDF_BLAS_CORETYPE=keep build/nbrdf --version 2>&1 | grep '^BLAS:')")
  second=$(second_coretype "$first")
  # OpenBLAS reads OPENBLAS_CORETYPE when it loads, and the CLI keeps one set in the
  # environment; NBRDF_BLAS_CORETYPE would override it, so it goes.
  run_env=(-u NBRDF_BLAS_CORETYPE -u NBRDF_BLAS_CHOSEN OPENBLAS_CORETYPE="$second")
  got=$(kernels_of "$(env "${run_env[@]}" build/nbrdf --version 2>&1 | grep '^BLAS:')")
  if [ -z "$first" ] || [ -z "$second" ]; then
    echo "== release, second BLAS kernels: none to try besides '$first' on this CPU; skipped"
  elif [ "${got,,}" != "${second,,}" ]; then
    echo "== release on $second kernels: OpenBLAS runs '$got' instead"
    failed=$((failed + 1))
  else
    run_tests build "release on $second kernels (first pass: $first)" "build/ctest-$second.log"
  fi
  run_env=()
fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
