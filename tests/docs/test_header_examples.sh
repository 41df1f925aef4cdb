#!/usr/bin/env bash
# Every example in a public header compiles against the headers as they are: a block
# opened by a comment line " * Example (...):" and made of the lines " *   code" that follow.
# It is compiled as the body of a function given `model` (a loaded bundle) and `in` (bake
# inputs), warnings as errors, so a renamed call or a wrong argument count fails here.
# The headers a user starts from must carry one.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
inc="$NBRDF_SOURCE_DIR/include"
cc=${CC:-cc}
found=0
for h in "$inc"/nbrdf/*.h; do
  name=$(basename "$h")
  awk -v out="$TMP/$name" '
    /^ \* Example \(/ { n++; inside = 1; next }
    inside && /^ \*   / { sub(/^ \*   /, ""); print > (out "." n ".body"); next }
    { inside = 0 }' "$h"
  for body in "$TMP/$name".*.body; do
    [ -e "$body" ] || continue
    found=$((found + 1))
    {
      echo '#include <stdio.h>'
      echo "#include \"nbrdf/$name\""
      echo '#include "nbrdf/nbrdf.h"'
      echo '#include "nbrdf/bake.h"'
      echo 'void header_example(const nbrdf_model *model, nbrdf_bake_inputs in);'
      echo 'void header_example(const nbrdf_model *model, nbrdf_bake_inputs in) {'
      echo '  (void)model, (void)in;'
      echo '  {' # an example may declare its own `in`
      cat "$body"
      echo '  }'
      echo '}'
    } >"$body.c"
    check "example $(basename "$body" .body) of $name compiles" \
      "$cc" -std=c11 -Wall -Wextra -Werror -fsyntax-only -I "$inc" "$body.c"
  done
done
check "headers carry examples (found $found)" test "$found" -ge 5
for name in bake.h verify.h model.h render.h brdf.h; do
  check "$name has an example" test -e "$TMP/$name.1.body"
done
finish
