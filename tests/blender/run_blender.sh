#!/usr/bin/env bash
# Runs tests/blender/NAME.py (each test_*.py is its own ctest test, blender/NAME:
# tests/CMakeLists.txt) headless in Blender (the add-on, issue 8) with $NBRDF, an untrained
# bundle and the packaged add-on zip; without NAME, every test_*.py in turn. One ctest test
# per script keeps each short: together they took more than ctest's 900 s on a loaded
# 2-core machine with a sanitizer build (issue 30, part 3). Blender missing is a failure,
# not a skip: CI installs it (scripts/setup-debian.sh).
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
if ! command -v blender >/dev/null 2>&1; then
  echo "FAIL: blender is not installed; run scripts/setup-debian.sh (apt-get install blender)" >&2
  exit 1
fi
"$NBRDF" bundle init "$TMP/bundle" --seed 1 >/dev/null || { echo "FAIL: bundle init" >&2; exit 1; }
zip=$TMP/nbrdf_bake.zip
check "package the add-on" bash "$NBRDF_SOURCE_DIR/scripts/package-blender-addon.sh" -o "$zip" \
  --nbrdf "$NBRDF" --bundle "$TMP/bundle"
mkdir -p "$TMP/tmp"

tests=("$NBRDF_SOURCE_DIR"/tests/blender/test_*.py)
[ $# -eq 0 ] || tests=("$NBRDF_SOURCE_DIR/tests/blender/$1.py")
for test in "${tests[@]}"; do
  name=$(basename "$test" .py)
  start=$SECONDS
  before=$failures
  check "$name (log: below)" env NBRDF_BUNDLE="$TMP/bundle" NBRDF_ADDON_ZIP="$zip" \
    BLENDER_USER_SCRIPTS="$TMP/scripts-$name" TMPDIR="$TMP/tmp" \
    blender -b --factory-startup --python-exit-code 1 --python "$test" >"$TMP/$name.log" 2>&1
  if [ "$failures" -ne "$before" ]; then
    sed 's/^/  | /' "$TMP/$name.log" >&2
    # Blender's own crash report (a backtrace) is what tells a crash in Blender from ours.
    for crash in "$TMP"/tmp/*.crash.txt; do
      [ -f "$crash" ] && sed 's/^/  crash | /' "$crash" >&2 && rm -f "$crash"
    done
  fi
  grep -E "^test_.*checks" "$TMP/$name.log"
  echo "$name: $((SECONDS - start)) s"
done
finish
