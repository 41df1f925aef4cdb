"""Preview Object: the active object's material, baked, rendered by `nbrdf render --mesh` on
the object itself, seen through the scene camera and lit by the world's environment image
(docs/BLENDER.md, "Preview Object"). It runs in the background like a bake (process.py:
progress, Esc / Cancel Preview); the image lands in an Image datablock shown in the panel
and in any open Image Editor. Turntable: N frames, the environment turned 360/N degrees each,
loaded as an image sequence."""

import os
import shutil
import tempfile

import bpy
from bpy.props import StringProperty

from . import lookdev_export, preferences
from .inputs import SetupError
from .process import BakeProcess

_running = {}


def running_preview():
    return _running.get("preview")


class Preview:
    """The frames of one preview: one render process at a time, then the image."""

    def __init__(self, material, argv_of, frames, folder):
        self.material_name = material.name
        self.argv_of = argv_of  # frame -> argv
        self.frames = frames
        self.folder = folder
        self.frame = 0
        self.process = None
        self.state = "running"
        self.message = ""
        self.image = None

    def png(self, frame):
        return os.path.join(self.folder, "preview_%04d.png" % (frame + 1))

    def start(self):
        self.process = BakeProcess(self.argv_of(self.frame), self.png(self.frame))
        if not self.process.start():
            self.state, self.message = "failed", self.process.message
            return False
        return True

    @property
    def progress(self):
        own = self.process.progress if self.process is not None else 0.0
        return (self.frame + own) / float(self.frames)

    def poll(self):
        if self.state != "running":
            return False
        if self.process.poll():
            return True
        if self.process.state != "done":
            self.state = self.process.state
            self.message = self.process.message
            shutil.rmtree(self.folder, ignore_errors=True)
            return False
        self.frame += 1
        if self.frame < self.frames:
            return self.start()
        self.state = "done"
        self.image = _load(self.png(0), self.frames, "nbrdf preview " + self.material_name)
        mat = bpy.data.materials.get(self.material_name)
        if mat is not None:
            mat.nbrdf_bake.lookdev_image = self.image
        if self.frames == 1:  # packed: the files are no longer needed
            shutil.rmtree(self.folder, ignore_errors=True)
        return False

    def wait(self, interval=0.05):
        import time
        while self.poll():
            time.sleep(interval)
        return self.state

    def cancel(self):
        if self.process is not None:
            self.process.cancel()


def _load(path, frames, name):
    """The PNG (frame 1 of a sequence when frames > 1) as an image datablock, replacing the
    last preview's pixels (packed: the temporary folder goes away)."""
    old = bpy.data.images.get(name)
    if old is not None:
        bpy.data.images.remove(old)
    im = bpy.data.images.load(path)
    im.name = name
    if frames > 1:
        im.source = "SEQUENCE"
    else:
        im.pack()
    im.size[0]
    return im


def _latent(material):
    res = material.nbrdf_bake.result
    path = bpy.path.abspath(res.filepath) if res is not None and res.filepath else ""
    if not path or not os.path.isfile(path):
        raise SetupError("material '%s' has no baked latent texture yet: bake it first"
                         % material.name)
    if res.source == "TILED":
        raise SetupError("the preview renders one latent texture, not a tile set")
    return path


def start_preview(context, obj=None):
    """Exports and starts the first frame; raises SetupError with a message to act on."""
    obj = obj if obj is not None else context.active_object
    if obj is None:
        raise SetupError("no active object to preview")
    mat = obj.active_material
    if mat is None:
        raise SetupError("'%s' has no material" % obj.name)
    latent = _latent(mat)
    exe, bundle, problem = preferences.resolve(preferences.get(context))
    if problem:
        raise SetupError(problem)
    s = mat.nbrdf_bake
    folder = tempfile.mkdtemp(prefix="nbrdf-lookdev-", dir=bpy.app.tempdir or None)
    try:
        mesh = os.path.join(folder, "object.glb")
        lookdev_export.export_object(obj, mesh)
        scene = context.scene
        cam = lookdev_export.camera_args(scene, s.lookdev_size[0], s.lookdev_size[1])
        env = lookdev_export.environment_image(scene, folder)
    except (SetupError, OSError, RuntimeError) as e:
        shutil.rmtree(folder, ignore_errors=True)
        raise SetupError(str(e)) from e
    frames = s.lookdev_frames if s.lookdev_turntable else 1
    base = lookdev_export.ENV_ROTATION_BASE

    def argv_of(frame):
        out = os.path.join(folder, "preview_%04d" % (frame + 1))
        argv = [exe, "render", latent, "--mesh", mesh, "-o", out + ".exr", "--png", out + ".png",
                "--bundle", bundle, "--width", str(s.lookdev_size[0]), "--height",
                str(s.lookdev_size[1]), "--spp", str(s.lookdev_spp), "--progress=json"]
        if env:
            argv += ["--env", env]
        argv += ["--env-rotation", "%.6g" % (base + 360.0 * frame / frames)]
        return argv + cam

    preview = Preview(mat, argv_of, frames, folder)
    if not preview.start():
        raise SetupError(preview.message)
    return preview


class NBRDF_OT_preview_object(bpy.types.Operator):
    """Render the baked neural material on the active object, through the scene camera, lit by
    the world's environment image (nbrdf render --mesh)"""
    bl_idname = "nbrdf.preview_object"
    bl_label = "Preview Object"

    @classmethod
    def poll(cls, context):
        return running_preview() is None and context.active_object is not None

    def _report_end(self, preview):
        if preview.state == "done":
            self.report({"INFO"}, "nbrdf: preview of '%s' in image '%s'"
                        % (preview.material_name, preview.image.name))
            _show(preview.image)
            return {"FINISHED"}
        self.report({"WARNING" if preview.state == "cancelled" else "ERROR"},
                    "nbrdf: preview %s: %s" % (preview.state, preview.message))
        return {"CANCELLED"}

    def _start(self, context):
        """The preview started and registered as running, or None (reported)."""
        try:
            preview = start_preview(context)
        except SetupError as e:
            self.report({"ERROR"}, "nbrdf: %s" % e)
            return None
        _running["preview"] = preview
        return preview

    def execute(self, context):
        preview = self._start(context)
        if preview is None:
            return {"CANCELLED"}
        try:
            preview.wait()
        finally:
            _running.pop("preview", None)
        return self._report_end(preview)

    def invoke(self, context, event):
        preview = self._start(context)
        if preview is None:
            return {"CANCELLED"}
        self._preview = preview
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        preview = self._preview
        if event.type == "ESC" and event.value == "PRESS":
            preview.cancel()
            return {"RUNNING_MODAL"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        still = preview.poll()
        context.window_manager.progress_update(100.0 * preview.progress)
        _redraw(context)
        if still:
            return {"PASS_THROUGH"}
        self._stop(context)
        return self._report_end(preview)

    def cancel(self, context):
        self._preview.cancel()
        self._preview.wait()
        self._stop(context)

    def _stop(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        _running.pop("preview", None)
        _redraw(context)


class NBRDF_OT_cancel_preview(bpy.types.Operator):
    """Stop the running preview render"""
    bl_idname = "nbrdf.cancel_preview"
    bl_label = "Cancel Preview"

    @classmethod
    def poll(cls, context):
        return running_preview() is not None

    def execute(self, context):
        running_preview().cancel()
        return {"FINISHED"}


class NBRDF_OT_show_preview(bpy.types.Operator):
    """Show the last preview in the open Image Editors"""
    bl_idname = "nbrdf.show_preview"
    bl_label = "Show in Image Editor"
    image: StringProperty(options={"SKIP_SAVE"})

    def execute(self, context):
        im = bpy.data.images.get(self.image)
        if im is None:
            return {"CANCELLED"}
        if not _show(im):
            self.report({"INFO"}, "nbrdf: open an Image Editor and pick '%s'" % im.name)
        return {"FINISHED"}


def _show(image):
    shown = False
    wm = bpy.context.window_manager
    for window in wm.windows if wm else ():
        for area in window.screen.areas:
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
                shown = True
    return shown


def _redraw(context):
    for window in context.window_manager.windows:
        for area in window.screen.areas:
            if area.type in {"PROPERTIES", "IMAGE_EDITOR"}:
                area.tag_redraw()


classes = (NBRDF_OT_preview_object, NBRDF_OT_cancel_preview, NBRDF_OT_show_preview)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
