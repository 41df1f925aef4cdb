#!/usr/bin/env bash
# Internal symbols carry their layer's prefix (core_, nn_, model_, ...): every
# global symbol of libnbrdf.a named nbrdf_* is a function of the public headers (the
# version script cmake makes from them, src/nbrdf.map), so a new internal helper named
# nbrdf_* fails here; every other global defined by an object of src/<layer>/ starts with
# <layer>_ (train/ also keeps trainer_, its training loop).
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

# The archive names its members by source file name only (csv.c.o), as src/CMakeLists.txt
# globs them from src/<layer>/: the source tree maps each member back to its layer, which
# holds while no two layers have a file of the same name (checked).
(cd "$NBRDF_SOURCE_DIR/src" && for f in */*.c */*.cpp; do
  [ -f "$f" ] && [ "${f%%/*}" != cli ] && echo "${f##*/}.o ${f%%/*}"
done) | sort >"$TMP/layers"
awk '{ print $1 }' "$TMP/layers" | uniq -d >"$TMP/same_name"
check "no two layers have a source file of the same name: $(tr '\n' ' ' <"$TMP/same_name")" \
  test ! -s "$TMP/same_name"
# Strong definitions only: weak ones (W, V) are C++ template and inline instances the shims
# pull in from the standard library and OIIO/OCIO. A named OpenMP critical section is a
# common symbol .gomp_critical_user_<name>: its name is checked like any other. Names the
# toolchain makes (AddressSanitizer's __odr_asan.<name> beside each global) are skipped: the
# global itself is checked.
nm -A -g --defined-only "$lib" 2>/dev/null | awk '
  { n = split($0, part, ":"); member = part[n - 1]; split(part[n], f, " ")
    if (f[2] ~ /^[TDBRCGS]$/ && f[3] !~ /^__/) {
      sym = f[3]; sub(/^\.gomp_critical_user_/, "", sym); print member, sym } }' |
  sort >"$TMP/members"
check "the archive has members" test -s "$TMP/members"
join -a 1 "$TMP/members" "$TMP/layers" | awk '
  NF < 3 { print $1 " (no src/<layer>/ source of this name)"; next }
  { name = $2
    # A C++ function in a namespace (_ZN<length><namespace>...): the namespace carries it.
    if (match(name, /^_ZN[0-9]+/)) name = substr(name, RLENGTH + 1, substr(name, 4, RLENGTH - 3))
    if (index(name, "nbrdf_") == 1 || index(name, $3 "_") == 1) next
    if ($3 == "train" && index($2, "trainer_") == 1) next
    print $2 " (src/" $3 "/" substr($1, 1, length($1) - 2) ")" }' >"$TMP/unprefixed"
check "every global carries its layer's prefix: $(tr '\n' ' ' <"$TMP/unprefixed")" \
  test ! -s "$TMP/unprefixed"
finish
