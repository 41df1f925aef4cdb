#!/usr/bin/env bash
# Builds nbrdf twice — optimised, and with AddressSanitizer + UBSan — and runs the
# whole test suite on both. Prints ctest's summary for each and a combined
# "N passed, N failed" line last. Exit status 0 only if every test passed.
set -uo pipefail
cd "$(dirname "$0")/.."

passed=0
failed=0
run_suite() { # run_suite BUILD_DIR LABEL CMAKE_ARGS...
  local dir=$1 label=$2; shift 2
  echo "== $label: build ($dir)"
  if ! bash scripts/build.sh "$dir" "$@"; then
    echo "== $label: build failed"
    failed=$((failed + 1))
    return
  fi
  echo "== $label: tests"
  local log="$dir/ctest.log"
  (cd "$dir" && ctest --output-on-failure --timeout 900 -j "$(nproc)") 2>&1 | tee "$log"
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

run_suite build "release"
if [ "${NBRDF_SKIP_SANITIZE:-0}" != 1 ]; then
  # Leak checks stay on; OpenMP's runtime keeps thread pools alive until exit, which
  # LeakSanitizer does not count as a leak.
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    run_suite build-sanitize "asan+ubsan" -DNBRDF_SANITIZE=ON -DNBRDF_BUILD_BENCH=OFF
fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
