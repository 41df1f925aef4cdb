#!/usr/bin/env bash
# The add-on's copy of the trained optical-depth maximum (blender_addon/nbrdf_bake/params.py,
# importable without Blender) equals the library's NBRDF_BAKE_SIGMA_T_MAX: the UI's default
# range and the bake's clamp must not drift apart.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
c=$(sed -n 's/^#define NBRDF_BAKE_SIGMA_T_MAX \([0-9.]*\)f\{0,1\}.*/\1/p' "$root/include/nbrdf/model.h")
[ -n "$c" ] || { echo "FAIL: NBRDF_BAKE_SIGMA_T_MAX not found in include/nbrdf/model.h"; exit 1; }
py=$(cd "$root/blender_addon/nbrdf_bake" && python3 -c 'import params; print(params.SIGMA_T_MAX)')
python3 -c "import sys; sys.exit(0 if float('$c') == float('$py') else 1)" ||
  { echo "FAIL: add-on SIGMA_T_MAX $py != NBRDF_BAKE_SIGMA_T_MAX $c"; exit 1; }
echo "ok: sigma_t max $c in both"
