#!/usr/bin/env bash
# Makes docs/images/blender-panel.png: Blender with a window under Xvfb bakes the default
# cube's material through the add-on and screenshots the nbrdf Latent Bake panel (docs/BLENDER.md).
# With --lookdev PNG it also runs Preview Object (docs/BLENDER.md, "Preview Object"), writes
# its render to PNG, and the screenshot shows the panel with it.
#   bash scripts/blender-panel-screenshot.sh [--nbrdf build/nbrdf] [--bundle models/default] [-o PNG]
#     [--lookdev PNG] [--scroll N]
# Needs blender and xvfb-run (Debian: apt-get install blender xvfb).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
nbrdf=$root/build/nbrdf
bundle=$root/models/default
out=$root/docs/images/blender-panel.png
lookdev=
scroll=24
while [ $# -gt 0 ]; do
  case $1 in
    --nbrdf) nbrdf=$2; shift 2 ;;
    --bundle) bundle=$2; shift 2 ;;
    -o) out=$2; shift 2 ;;
    --lookdev) lookdev=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
    --scroll) scroll=$2; shift 2 ;;
    *) echo "blender-panel-screenshot: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
env NBRDF_SOURCE_DIR="$root" NBRDF="$(cd "$(dirname "$nbrdf")" && pwd)/$(basename "$nbrdf")" \
  NBRDF_BUNDLE="$(cd "$bundle" && pwd)" SHOT="$work/shot.png" WORK="$work" \
  LOOKDEV="$lookdev" SCROLL="$scroll" \
  BLENDER_USER_SCRIPTS="$work/scripts" \
  xvfb-run -a -s "-screen 0 1100x1500x24" \
  blender --factory-startup --window-geometry 0 0 1100 1500 --python "$root/scripts/blender-panel-shot.py"
test -s "$work/shot.png" || { echo "blender-panel-screenshot: no screenshot" >&2; exit 1; }
mkdir -p "$(dirname "$out")"
cp "$work/shot.png" "$out"
echo "wrote $out ($(stat -c %s "$out") bytes)"
