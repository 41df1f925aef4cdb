"""Shared by tests/blender/test_*.py (run inside Blender by run_blender.sh).

Environment: NBRDF (the CLI), NBRDF_BUNDLE (an untrained bundle), NBRDF_SOURCE_DIR.
A failed check is printed and counted; finish() raises so Blender exits 1
(--python-exit-code 1).
"""

import os
import sys
import tempfile

import addon_utils
import bpy

SOURCE = os.environ["NBRDF_SOURCE_DIR"]
NBRDF = os.environ["NBRDF"]
BUNDLE = os.environ["NBRDF_BUNDLE"]
ADDON = "nbrdf_bake"

_state = {"checks": 0, "failures": 0}


def check(what, ok):
    _state["checks"] += 1
    if not ok:
        _state["failures"] += 1
        print("FAIL: %s" % what, file=sys.stderr)
    return ok


def finish(name):
    print("%s: %d checks, %d failed" % (name, _state["checks"], _state["failures"]))
    if _state["failures"]:
        raise SystemExit(1)


def enable(configure=True):
    """Enables the add-on from the source tree; points it at $NBRDF and $NBRDF_BUNDLE."""
    folder = os.path.join(SOURCE, "blender_addon")
    if folder not in sys.path:
        sys.path.insert(0, folder)
    errors = []
    mod = addon_utils.enable(ADDON, default_set=True, handle_error=errors.append)
    if mod is None or errors:
        raise RuntimeError("enabling %s failed: %s" % (ADDON, errors))
    if configure:
        prefs = bpy.context.preferences.addons[ADDON].preferences
        prefs.nbrdf_path = NBRDF
        prefs.bundle_dir = BUNDLE
    return mod


def disable():
    addon_utils.disable(ADDON, default_set=True)


def temp_dir():
    return tempfile.mkdtemp(prefix="nbrdf-blender-test-")


def bake_temp_dirs():
    """The add-on's temporary input folders that currently exist."""
    base = bpy.app.tempdir or tempfile.gettempdir()
    return [e for e in os.listdir(base) if e.startswith("nbrdf-bake-")]


def temporaries(folder):
    return [e for e in os.listdir(folder) if e.endswith(".tmp")]
