#!/usr/bin/env bash
# Zips the Blender add-on (blender_addon/nbrdf_bake) for Edit > Preferences > Add-ons >
# Install. Optionally puts the nbrdf executable in the add-on's bin/ and a model bundle in
# its models/default, where the add-on finds them without any setting (docs/BLENDER.md).
#   bash scripts/package-blender-addon.sh [-o OUT.zip] [--nbrdf PATH] [--bundle DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=nbrdf_bake.zip
nbrdf=""
bundle=""
while [ $# -gt 0 ]; do
  case $1 in
    -o) out=$2; shift 2 ;;
    --nbrdf) nbrdf=$2; shift 2 ;;
    --bundle) bundle=$2; shift 2 ;;
    -h|--help) sed -n '2,5p' "$0"; exit 0 ;;
    *) echo "package-blender-addon: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
case $out in /*) ;; *) out=$PWD/$out ;; esac
[ -z "$nbrdf" ] || [ -x "$nbrdf" ] || { echo "package-blender-addon: '$nbrdf' is not an executable" >&2; exit 1; }
[ -z "$bundle" ] || [ -f "$bundle/model.json" ] || { echo "package-blender-addon: '$bundle' has no model.json" >&2; exit 1; }

stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir "$stage/nbrdf_bake"
(cd "$root/blender_addon/nbrdf_bake" && find . -name '*.py' -exec cp --parents {} "$stage/nbrdf_bake/" \;)
if [ -n "$nbrdf" ]; then
  mkdir "$stage/nbrdf_bake/bin"
  cp "$nbrdf" "$stage/nbrdf_bake/bin/nbrdf"
fi
if [ -n "$bundle" ]; then
  mkdir -p "$stage/nbrdf_bake/models"
  cp -r "$bundle" "$stage/nbrdf_bake/models/default"
fi
# Written beside the destination and renamed: a failed run leaves no half zip.
tmp="$out.$$.tmp"
(cd "$stage" && cmake -E tar cf "$tmp" --format=zip nbrdf_bake)
mv "$tmp" "$out"
echo "wrote $out ($(du -k "$out" | cut -f1) KiB)"
