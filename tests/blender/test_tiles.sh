#!/usr/bin/env bash
# Plain Python (no Blender): the add-on's tile patterns, tiles.py.
exec python3 "$NBRDF_SOURCE_DIR/tests/blender/unit_tiles.py"
