#!/usr/bin/env bash
# The add-on's Principled BSDF mapping table (blender_addon/nbrdf_bake/principled.py) in plain
# Python, without Blender: the 4.x socket names are tested here (the build machine has 3.4).
exec python3 "$NBRDF_SOURCE_DIR/tests/blender/unit_principled.py"
