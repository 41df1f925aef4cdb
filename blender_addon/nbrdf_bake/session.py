"""One bake of one material: inputs written, CLI running, result loaded, temp files gone;
then, when asked for and available, a preview render of the texture.

The operator is a thin shell over this: execute() calls start() then wait(); the modal
invoke() calls start() and then poll() on a timer. Tests drive it the same way.
"""

import os
import shutil
import subprocess
import tempfile
import time

import bpy

from . import inputs, preferences
from .process import BakeProcess


class Session:
    def __init__(self, material_name, bake, workdir, preview_argv):
        self.material_name = material_name
        self.bake = bake
        self.preview = None
        self.process = bake  # the one running now
        self.workdir = workdir
        self.preview_argv = preview_argv
        self.image = None
        self.preview_image = None

    @classmethod
    def start(cls, context, material):
        """Starts a bake; raises inputs.SetupError with a message the user can act on."""
        exe, bundle, problem = preferences.resolve(preferences.get(context))
        if problem:
            raise inputs.SetupError(problem)
        settings = material.nbrdf_bake
        workdir = tempfile.mkdtemp(prefix="nbrdf-bake-", dir=bpy.app.tempdir or None)
        try:
            argv, output = inputs.build_argv(exe, bundle, settings, material.name, workdir)
            os.makedirs(os.path.dirname(output), exist_ok=True)
        except (inputs.SetupError, OSError) as e:
            shutil.rmtree(workdir, ignore_errors=True)
            if isinstance(e, OSError):
                raise inputs.SetupError("cannot prepare the bake: %s" % e) from e
            raise
        preview_argv = None
        if settings.preview and has_render(exe):
            size = str(settings.preview_size)
            preview_argv = [exe, "render", output, "-o", preview_path(output), "--bundle", bundle,
                            "--width", size, "--height", size, "--spp",
                            str(settings.preview_spp), "--progress=json"]
        bake = BakeProcess(argv, output, cwd=workdir)
        session = cls(material.name, bake, workdir, preview_argv)
        if not bake.start():
            session._cleanup()
            raise inputs.SetupError(bake.message)
        return session

    @property
    def stage(self):
        return "preview" if self.process is self.preview else "bake"

    @property
    def progress(self):
        return self.process.progress

    @property
    def cancelling(self):
        return self.process.cancelling

    def poll(self):
        """True while running; at the end the inputs are removed and the results loaded."""
        if self.process.poll():
            return True
        material = bpy.data.materials.get(self.material_name)
        if self.process is self.bake:
            self._cleanup()
            if self.bake.state != "done":
                return False
            self.image = load_result(self.bake.output)
            if material is not None:
                material.nbrdf_bake.result = self.image
            if self.preview_argv:
                self.preview = BakeProcess(self.preview_argv, preview_path(self.bake.output))
                self.process = self.preview
                return self.preview.start()
            return False
        if self.preview.state == "done":
            self.preview_image = load_result(self.preview.output)
            if material is not None:
                material.nbrdf_bake.preview_image = self.preview_image
        return False

    def wait(self, interval=0.05):
        while self.poll():
            time.sleep(interval)
        return self.bake.state

    def cancel(self):
        self.process.cancel()

    def report(self):
        """(level, text) for Blender's report area once the session has ended."""
        b = self.bake
        if b.state == "cancelled":
            return "WARNING", "nbrdf: bake " + b.message
        if b.state != "done":
            return "ERROR", "nbrdf bake failed: " + b.message
        r = b.result
        notes = list(b.warnings)
        if self.preview is not None and self.preview.state != "done":
            notes.append("preview not rendered: " + self.preview.message)
        text = "nbrdf: baked %s (%s x %s, %s)" % (b.output, r.get("width"), r.get("height"),
                                                  "rgb" if r.get("channels") == 3 else "mono")
        return ("WARNING" if notes else "INFO"), "; ".join([text] + notes)

    def _cleanup(self):
        shutil.rmtree(self.workdir, ignore_errors=True)


def preview_path(output):
    return os.path.splitext(output)[0] + ".preview.exr"


# (path, mtime) -> whether that executable has `render`; asked once, not on every bake.
_render_support = {}


def has_render(exe):
    """Whether this nbrdf has the render subcommand (older builds answer 'unknown')."""
    try:
        key = (exe, os.stat(exe).st_mtime_ns)
    except OSError:
        return False
    if key not in _render_support:
        try:
            _render_support[key] = subprocess.run(
                [exe, "render", "--help"], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL, timeout=30).returncode == 0
        except (OSError, subprocess.TimeoutExpired):
            return False
    return _render_support[key]


def load_result(path):
    """An EXR as an image datablock, reloaded when one already shows that file. The latent
    texture becomes MULTILAYER (layers latent and proxy) once Blender reads its header."""
    image = None
    for im in bpy.data.images:
        if im.filepath and os.path.normpath(bpy.path.abspath(im.filepath)) == path:
            image = im
            break
    if image is None:
        image = bpy.data.images.load(path)
    else:
        image.reload()
    # Reading the size makes Blender open the file and see its layers now. (Setting a colour
    # space here would turn it back into a plain IMAGE: float EXR data is never converted.)
    image.size[0]
    return image
