"""One bake of one material: inputs written, CLI running, result loaded, temp files gone.

The operator is a thin shell over this: execute() calls start() then wait(); the modal
invoke() calls start() and then poll() on a timer. Tests drive it the same way.
"""

import os
import shutil
import tempfile

import bpy

from . import inputs, preferences
from .process import BakeProcess


class Session:
    def __init__(self, material_name, process, workdir):
        self.material_name = material_name
        self.process = process
        self.workdir = workdir
        self.image = None

    @classmethod
    def start(cls, context, material):
        """Starts a bake; raises inputs.SetupError with a message the user can act on."""
        exe, bundle, problem = preferences.resolve(preferences.get(context))
        if problem:
            raise inputs.SetupError(problem)
        workdir = tempfile.mkdtemp(prefix="nbrdf-bake-", dir=bpy.app.tempdir or None)
        try:
            argv, output = inputs.build_argv(exe, bundle, material.nbrdf_bake, material.name,
                                             workdir)
            os.makedirs(os.path.dirname(output), exist_ok=True)
        except (inputs.SetupError, OSError) as e:
            shutil.rmtree(workdir, ignore_errors=True)
            if isinstance(e, OSError):
                raise inputs.SetupError("cannot prepare the bake: %s" % e) from e
            raise
        process = BakeProcess(argv, output, cwd=workdir)
        session = cls(material.name, process, workdir)
        if not process.start():
            session._cleanup()
            raise inputs.SetupError(process.message)
        return session

    @property
    def progress(self):
        return self.process.progress

    def poll(self):
        """True while running; at the end the inputs are removed and the result loaded."""
        if self.process.poll():
            return True
        self._cleanup()
        if self.process.state == "done":
            self.image = load_result(self.process.output)
            material = bpy.data.materials.get(self.material_name)
            if material is not None:
                material.nbrdf_bake.result = self.image
        return False

    def wait(self, interval=0.05):
        import time
        while self.poll():
            time.sleep(interval)
        return self.process.state

    def cancel(self):
        self.process.cancel()

    def report(self):
        """(level, text) for Blender's report area once the bake has ended."""
        p = self.process
        if p.state == "done":
            r = p.result
            text = "nbrdf: baked %s (%s x %s, %s)" % (p.output, r.get("width"), r.get("height"),
                                                      "rgb" if r.get("channels") == 3 else "mono")
            if p.warnings:
                text += "; " + "; ".join(p.warnings)
            return "WARNING" if p.warnings else "INFO", text
        if p.state == "cancelled":
            return "WARNING", "nbrdf: " + p.message
        return "ERROR", "nbrdf bake failed: " + p.message

    def _cleanup(self):
        shutil.rmtree(self.workdir, ignore_errors=True)


def load_result(path):
    """The latent EXR as an image datablock (MULTILAYER once Blender reads its header)."""
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
