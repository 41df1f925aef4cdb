"""Bake Latent Texture (modal with progress and Esc, or blocking from scripts), Cancel, Use
Material and Write Farm Plan."""

import bpy
from bpy.props import StringProperty

from . import farm, material_inputs, principled
from .inputs import SetupError
from .session import Session

# The bake in progress, if any. Kept here rather than in a property so that a .blend saved
# during a bake never reopens believing one is running.
_running = {}


def running_session():
    return _running.get("session")


def _material(context, name):
    if name:
        return bpy.data.materials.get(name)
    mat = getattr(context, "material", None)
    if mat is None and getattr(context, "object", None) is not None:
        mat = context.object.active_material
    return mat


class NBRDF_OT_bake_latent(bpy.types.Operator):
    """Bake the material's layered parameters into a latent texture with nbrdf"""
    bl_idname = "nbrdf.bake_latent"
    bl_label = "Bake Latent Texture"
    bl_options = {"REGISTER", "UNDO"}

    material: StringProperty(name="Material", options={"SKIP_SAVE"},
                             description="Material to bake (default: the active one)")

    @classmethod
    def poll(cls, context):
        from .queue import running_queue
        return running_session() is None and running_queue() is None

    def _start(self, context):
        mat = _material(context, self.material)
        if mat is None:
            self.report({"ERROR"}, "nbrdf: no material to bake (material '%s' not found)"
                        % self.material if self.material else "nbrdf: no active material")
            return None
        try:
            return Session.start(context, mat)
        except SetupError as e:
            self.report({"ERROR"}, "nbrdf: %s" % e)
            return None

    def _end(self, session):
        level, text = session.report()
        self.report({level}, text)
        return {"FINISHED"} if session.bake.state == "done" else {"CANCELLED"}

    def execute(self, context):
        # Blocking: for scripts and `blender -b`, where modal timers do not run.
        session = self._start(context)
        if session is None:
            return {"CANCELLED"}
        session.wait()
        return self._end(session)

    def invoke(self, context, event):
        session = self._start(context)
        if session is None:
            return {"CANCELLED"}
        _running["session"] = session
        wm = context.window_manager
        self._session = session
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        context.workspace.status_text_set("nbrdf: baking %s (Esc to cancel)"
                                          % session.material_name)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        session = self._session
        if event.type == "ESC" and event.value == "PRESS":
            session.cancel()
            return {"RUNNING_MODAL"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        still = session.poll()
        context.window_manager.progress_update(100.0 * session.progress)
        _redraw(context)
        if still:
            return {"PASS_THROUGH"}
        self._stop(context)
        return self._end(session)

    def cancel(self, context):
        # Blender ends the modal operator (file loaded, window closed): stop the child too.
        session = self._session
        session.cancel()
        session.wait()
        self._stop(context)

    def _stop(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        if context.workspace is not None:
            context.workspace.status_text_set(None)
        _running.pop("session", None)
        _redraw(context)


class NBRDF_OT_cancel_bake(bpy.types.Operator):
    """Stop the running bake; it leaves no file"""
    bl_idname = "nbrdf.cancel_bake"
    bl_label = "Cancel Bake"

    @classmethod
    def poll(cls, context):
        return running_session() is not None

    def execute(self, context):
        running_session().cancel()
        return {"FINISHED"}


class NBRDF_OT_use_material(bpy.types.Operator):
    """Read the coat roughness, coat IOR, base roughness and base reflectance from the
    material's Principled BSDF (each can still be set by hand afterwards)"""
    bl_idname = "nbrdf.use_material"
    bl_label = "Use Material"
    bl_options = {"REGISTER", "UNDO"}

    material: StringProperty(name="Material", options={"SKIP_SAVE"},
                             description="Material (default: the active one)")

    @classmethod
    def poll(cls, context):
        return running_session() is None

    def execute(self, context):
        mat = _material(context, self.material)
        if mat is None:
            self.report({"ERROR"}, "nbrdf: no material")
            return {"CANCELLED"}
        try:
            reading, notes = material_inputs.read(mat)
        except material_inputs.MaterialError as e:
            self.report({"ERROR"}, "nbrdf: %s" % e)
            return {"CANCELLED"}
        s = mat.nbrdf_bake
        for key in principled.mapped_keys():
            setattr(s, key + "_source", "MATERIAL")
            notes += [n for n in reading[key].notes]
        if any(r.kind == "procedural" for r in reading.values()) and not s.bake_uv:
            notes.append("procedural inputs need Bake Through UV Map")
        self.report({"WARNING"} if notes else {"INFO"},
                    "nbrdf: %s reads its Principled BSDF%s" % (
                        mat.name, ("; " + "; ".join(notes)) if notes else ""))
        return {"FINISHED"}


class NBRDF_OT_write_farm_plan(bpy.types.Operator):
    """Write a Slurm farm plan for the material's tile set (nbrdf farm slurm --plan, not
    submitted): the folder, its submit.sh and plan.json; no Slurm needed here"""
    bl_idname = "nbrdf.write_farm_plan"
    bl_label = "Write Farm Plan"
    bl_options = {"REGISTER"}

    material: StringProperty(name="Material", options={"SKIP_SAVE"},
                             description="Material (default: the active one)")

    @classmethod
    def poll(cls, context):
        from .queue import running_queue
        return running_session() is None and running_queue() is None

    def execute(self, context):
        mat = _material(context, self.material)
        if mat is None:
            self.report({"ERROR"}, "nbrdf: no material")
            return {"CANCELLED"}
        try:
            plan = farm.write_plan(context, mat)
        except SetupError as e:
            mat.nbrdf_bake.farm_report = ""
            self.report({"ERROR"}, "nbrdf: %s" % e)
            return {"CANCELLED"}
        mat.nbrdf_bake.farm_report = plan.report()
        self.report({"INFO"}, "nbrdf: " + plan.report())
        return {"FINISHED"}


def _redraw(context):
    for window in context.window_manager.windows:
        for area in window.screen.areas:
            if area.type in {"PROPERTIES", "NODE_EDITOR"}:
                area.tag_redraw()


classes = (NBRDF_OT_bake_latent, NBRDF_OT_cancel_bake, NBRDF_OT_use_material,
           NBRDF_OT_write_farm_plan)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    session = running_session()
    if session is not None:  # never leave a bake running behind a disabled add-on
        session.cancel()
        session.wait()
        _running.clear()
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
