#!/usr/bin/env bash
# Internal symbols carry their layer's prefix (core_, nn_, model_, ...; issue 16): every
# global symbol of libnbrdf.a named nbrdf_* is a function of the public headers (the
# version script cmake makes from them, src/nbrdf.map), so a new internal helper named
# nbrdf_* fails here.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
lib="$(dirname "$NBRDF")/src/libnbrdf.a"
map="$(dirname "$NBRDF")/src/nbrdf.map"
check "the static library exists" test -f "$lib"
check "the version script exists" test -f "$map"
nm -g --defined-only "$lib" 2>/dev/null | awk '$3 ~ /^nbrdf_/ { print $3 }' | sort -u >"$TMP/defined"
sed -n 's/^ *\(nbrdf_[a-z0-9_]*\);$/\1/p' "$map" | sort -u >"$TMP/public"
check "some public symbols are defined" test "$(wc -l <"$TMP/defined")" -gt 20
comm -23 "$TMP/defined" "$TMP/public" >"$TMP/internal"
check "no internal nbrdf_ symbol: $(tr '\n' ' ' <"$TMP/internal")" test ! -s "$TMP/internal"
finish
