#!/usr/bin/env bash
# The Markdown of the repository is read where it lies (a checkout, a source package),
# where nothing outside the repository exists, so a relative path in it must stay inside
# the repository and name something that exists. Checked in every *.md outside build
# folders, .git and the ignored work folders (data/, runs/, fuzz-out/):
# - every Markdown link target [text](target) that is not a URL (scheme:) or an anchor
#   (#...): resolved against the document's folder, it exists and lies inside the root;
# - every path spelled with a leading ../ anywhere in the text (links are not the only way
#   a doc points elsewhere): the same, except inside `code` spans, which spell paths of
#   the command or program shown (`../share/nbrdf/models/default` beside an executable);
# - no absolute path under /work/ (the build machines' layout, not the repository's).
# Fenced code blocks are skipped for the first two: their paths belong to the command shown.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
root=$(realpath "$NBRDF_SOURCE_DIR")

# Prints "line<TAB>target" for each link target and each ../ path outside code fences.
targets() {
  awk '
    /^ *```/ { fence = !fence; next }
    fence { next }
    {
      line = $0
      while (match(line, /\]\([^)]*\)/)) {
        t = substr(line, RSTART + 2, RLENGTH - 3)
        sub(/[ \t]+".*$/, "", t)
        print NR "\t" t
        line = substr(line, RSTART + RLENGTH)
      }
      line = $0
      gsub(/`[^`]*`/, "", line)
      while (match(line, /(^|[^A-Za-z0-9_.\/-])\.\.\/[A-Za-z0-9_.\/-]*/)) {
        t = substr(line, RSTART, RLENGTH)
        sub(/^[^.]/, "", t)
        sub(/[.]+$/, "", t)
        print NR "\t" t
        line = substr(line, RSTART + RLENGTH)
      }
    }' "$1" | sort -u
}

docs=0
links=0
: >"$TMP/bad"
while IFS= read -r -d '' doc; do
  docs=$((docs + 1))
  rel=${doc#"$root"/}
  dir=$(dirname "$doc")
  while IFS=$'\t' read -r line target; do
    case $target in
      '' | '#'* | [A-Za-z]*:*) continue ;;
    esac
    links=$((links + 1))
    path=${target%%#*}
    [ -n "$path" ] || continue
    # A bare "../" (a doc speaking of such spellings, not pointing anywhere) names no file.
    [ "$path" = "../" ] && continue
    case $path in
      /*) resolved=$path ;;
      *) resolved=$(realpath -m "$dir/$path") ;;
    esac
    case $resolved in
      "$root" | "$root"/*) ;;
      *) echo "$rel:$line: '$target' leaves the repository" >>"$TMP/bad"; continue ;;
    esac
    [ -e "$resolved" ] || echo "$rel:$line: '$target' does not exist" >>"$TMP/bad"
  done < <(targets "$doc")
  grep -n '/work/' "$doc" | sed "s|^\([0-9]*\):.*|$rel:\1: names a path under /work/ (outside the repository)|" \
    >>"$TMP/bad"
done < <(find "$root" \( -path "$root/build*" -o -path "$root/.git" -o -path "$root/data" \
  -o -path "$root/runs" -o -path "$root/fuzz-out" \) -prune -o -name '*.md' -print0)

cat "$TMP/bad" >&2
check "every relative path in $docs documents resolves inside the repository ($links checked)" \
  test ! -s "$TMP/bad"
check "documents were found" test "$docs" -ge 20
check "links were found" test "$links" -ge 30
finish
