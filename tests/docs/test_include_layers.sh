#!/usr/bin/env bash
# The house drawn from includes (scripts/check_includes.py): in src/, no #include points
# to a higher layer of docs/ARCHITECTURE.md's list, and no new cycle joins a layer's
# modules. The checker itself must catch both: a copy of the tree gets one of each.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
check_py="$NBRDF_SOURCE_DIR/scripts/check_includes.py"
check "the source tree's includes point down, no new cycle" python3 "$check_py" "$NBRDF_SOURCE_DIR"

mkdir -p "$TMP/tree/docs" "$TMP/tree/src/core" "$TMP/tree/src/model" "$TMP/tree/include/nbrdf"
cp "$NBRDF_SOURCE_DIR/docs/ARCHITECTURE.md" "$TMP/tree/docs/"
echo '#include "model/a.h"' >"$TMP/tree/src/core/up.c"
printf '#include "model/b.h"\n' >"$TMP/tree/src/model/a.h"
printf '#include "model/a.h"\n' >"$TMP/tree/src/model/b.h"
python3 "$check_py" "$TMP/tree" >"$TMP/out" 2>&1
check "a planted upward include and cycle fail" test $? -ne 0
check "the upward include is named" grep -q 'upward: src/core/up.c includes model/a (core -> model)' "$TMP/out"
check "the cycle is named" grep -q 'cycle in model: model/a, model/b' "$TMP/out"
finish
