"""Finds the nbrdf executable and the model bundle, without bpy.

Order: the path set in the preferences; then next to the add-on folder, in its bin/, and on
PATH (executable); the add-on's models/default and the folders around the executable
(bundle). A path set but wrong is an error, never silently replaced by a found one.
"""

import os
import shutil
import subprocess

EXE = "nbrdf.exe" if os.name == "nt" else "nbrdf"


class NotFound(Exception):
    pass


def _is_exe(path):
    return os.path.isfile(path) and os.access(path, os.X_OK)


def _is_bundle(path):
    return os.path.isfile(os.path.join(path, "model.json"))


def _restore_exec_bit(path):
    """Blender's add-on installer extracts zips without file modes: a bundled nbrdf arrives
    without its executable bit. Only the add-on's own copy is touched."""
    if os.name == "posix" and os.path.isfile(path) and not os.access(path, os.X_OK):
        try:
            os.chmod(path, os.stat(path).st_mode | 0o755)
        except OSError:
            pass


def find_nbrdf(configured, addon_dir):
    if configured:
        path = os.path.abspath(os.path.expanduser(configured))
        if _is_exe(path):
            return path
        raise NotFound("nbrdf executable: the path set in the add-on preferences, '%s', is not "
                       "an executable file" % configured)
    places = [os.path.join(addon_dir, EXE), os.path.join(addon_dir, "bin", EXE),
              os.path.join(os.path.dirname(addon_dir), EXE)]
    for p in places[:2]:
        _restore_exec_bit(p)
    for p in places:
        if _is_exe(p):
            return p
    found = shutil.which(EXE)
    if found:
        return os.path.abspath(found)
    raise NotFound("nbrdf executable not found (looked in %s and on PATH): set it in Edit > "
                   "Preferences > Add-ons > nbrdf Bake, or install it next to the add-on"
                   % ", ".join(places))


def find_bundle(configured, addon_dir, nbrdf_path=None):
    if configured:
        path = os.path.abspath(os.path.expanduser(configured))
        if _is_bundle(path):
            return path
        raise NotFound("model bundle: the folder set in the add-on preferences, '%s', has no "
                       "model.json" % configured)
    places = [os.path.join(addon_dir, "models", "default")]
    if nbrdf_path:
        exe_dir = os.path.dirname(nbrdf_path)
        places += [os.path.join(exe_dir, "models", "default"),
                   os.path.join(exe_dir, "..", "models", "default"),
                   os.path.join(exe_dir, "..", "share", "nbrdf", "models", "default")]
    for p in places:
        if _is_bundle(p):
            return os.path.normpath(p)
    raise NotFound("model bundle not found (looked in %s): set its folder in Edit > Preferences "
                   "> Add-ons > nbrdf Bake ('nbrdf bundle init DIR' makes an untrained one)"
                   % ", ".join(os.path.normpath(p) for p in places))


# (path, mtime) -> None or why it does not run: asked once per executable, not every redraw.
_runs = {}


def check_runs(exe):
    """None when `exe --version` runs, else a message saying what is missing. A copied nbrdf
    needs the shared libraries it was linked with (OpenImageIO, OpenEXR, a BLAS, ...): on
    another machine the loader refuses it before nbrdf can say anything."""
    try:
        key = (exe, os.stat(exe).st_mtime_ns)
    except OSError as e:
        return "nbrdf executable '%s': %s" % (exe, e.strerror or e)
    if key not in _runs:
        try:
            r = subprocess.run([exe, "--version"], stdin=subprocess.DEVNULL,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=30,
                               text=True, errors="replace")
            lines = [l.strip() for l in r.stderr.splitlines() if l.strip()]
            why = None if r.returncode == 0 else (
                lines[0] if lines else "exit status %d" % r.returncode)
        except subprocess.TimeoutExpired:
            why = "'--version' did not answer within 30 s"
        except OSError as e:
            why = e.strerror or str(e)
        _runs[key] = None if why is None else (
            "nbrdf executable '%s' does not run here (%s). It needs the shared libraries it "
            "was built with (OpenImageIO, OpenEXR, OpenBLAS, ...): install nbrdf for this "
            "system and set its path in Edit > Preferences > Add-ons > nbrdf Bake" % (exe, why))
    return _runs[key]
