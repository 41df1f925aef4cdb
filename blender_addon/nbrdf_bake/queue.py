"""Bake All Materials: a queue of one bake per material and object (selected objects or the
whole scene), each with its state (pending, baking, done, failed, cancelled) and message,
kept on the scene and shown in a list. One bake runs at a time through session.Session; a
failure is recorded and the queue goes on; one item or all can be cancelled.

The runner is plain Python over Session, so the blocking execute() (scripts, `blender -b`),
the modal invoke() and the tests all drive the same code.
"""

import time

import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, IntProperty,
                       PointerProperty, StringProperty)

from . import principled
from .inputs import SetupError
from .session import Session

STATES = [("PENDING", "Pending", "Waiting for its turn", "SORTTIME", 0),
          ("BAKING", "Baking", "Baking now", "TIME", 1),
          ("DONE", "Done", "Written", "CHECKMARK", 2),
          ("FAILED", "Failed", "Failed: the message says why", "ERROR", 3),
          ("CANCELLED", "Cancelled", "Cancelled: no file written", "CANCEL", 4)]
ICONS = {s[0]: s[3] for s in STATES}


class NBRDF_QueueItem(bpy.types.PropertyGroup):
    object_name: StringProperty(name="Object")
    material_name: StringProperty(name="Material")
    state: EnumProperty(name="State", items=STATES, default="PENDING")
    message: StringProperty(name="Message", description="Why it failed, or what it wrote")
    output: StringProperty(name="Output", subtype="FILE_PATH")


class NBRDF_QueueSettings(bpy.types.PropertyGroup):
    items: CollectionProperty(type=NBRDF_QueueItem)
    index: IntProperty(name="Item", default=0)
    scope: EnumProperty(
        name="Objects", default="SELECTED",
        items=[("SELECTED", "Selected", "Every material of the selected objects"),
               ("SCENE", "Scene", "Every material of the scene's objects")])
    output: StringProperty(
        name="Output", subtype="FILE_PATH", default="//latent/{object}_{material}.exr",
        description="Latent texture of each item ({object}, {material}: their names; // is "
                    "the .blend file's folder)")
    uv_map: StringProperty(
        name="UV Map", default="",
        description="UV map that procedural inputs are baked over (Bake Through UV Map); "
                    "empty: each object's active UV map")
    read_material: BoolProperty(
        name="Read Principled BSDF", default=True,
        description="Set each material's coat and base parameters to come from its Principled "
                    "BSDF first (as Use Material does); off: each material's own settings")
    bake_uv: BoolProperty(
        name="Bake Through UV Map", default=False,
        description="Turn on each material's Bake Through UV Map, so that inputs from "
                    "procedural nodes are baked over the UV map first")


def gather(context, scope):
    """[(object, material)] in order: each mesh object of the scope, each of its materials
    once (slots without a material are skipped)."""
    objects = context.selected_objects if scope == "SELECTED" else context.scene.objects
    out = []
    for obj in sorted(objects, key=lambda o: o.name):
        if obj.type != "MESH":
            continue
        seen = set()
        for slot in obj.material_slots:
            m = slot.material
            if m is not None and m.name not in seen:
                seen.add(m.name)
                out.append((obj, m))
    return out


class QueueRunner:
    """Steps through the scene's queue: step() until it returns False."""

    def __init__(self, scene):
        self.scene_name = scene.name
        self.session = None
        self.index = -1

    @property
    def queue(self):
        scene = bpy.data.scenes.get(self.scene_name)
        return scene.nbrdf_queue if scene is not None else None

    def step(self, context):
        """Polls the running bake, or starts the next pending item; False when none is left."""
        q = self.queue
        if q is None:
            return False
        if self.session is not None:
            if self.session.poll():
                return True
            self._finish(q.items[self.index] if self.index < len(q.items) else None)
        for i, item in enumerate(q.items):
            if item.state == "PENDING":
                self._start(context, q, i, item)
                return True
        return False

    def _start(self, context, q, i, item):
        self.index = i
        q.index = i
        obj = bpy.data.objects.get(item.object_name)
        mat = bpy.data.materials.get(item.material_name)
        if obj is None or mat is None:
            item.state, item.message = "FAILED", "object or material no longer exists"
            return
        if q.read_material and mat.nbrdf_bake is not None:
            for key in principled.mapped_keys():
                setattr(mat.nbrdf_bake, key + "_source", "MATERIAL")
            mat.nbrdf_bake.roughness = "PERCEPTUAL"
        if q.bake_uv:
            mat.nbrdf_bake.bake_uv = True
        item.state, item.message = "BAKING", ""
        try:
            self.session = Session.start(context, mat, obj, q.output, q.uv_map or None,
                                         extras=False)
        except SetupError as e:
            item.state, item.message = "FAILED", str(e)
            self.session = None
            return
        item.output = self.session.bake.output

    def _finish(self, item):
        s, self.session = self.session, None
        if item is None:
            return
        state = s.bake.state
        item.state = {"done": "DONE", "cancelled": "CANCELLED"}.get(state, "FAILED")
        ranges = s.ranges
        if state == "done":
            item.message = "; ".join(["wrote " + s.bake.output] + ranges)
        elif state == "cancelled":  # a tile set keeps its finished tiles: the message says
            item.message = s.bake.message or "cancelled; no file written"
        else:
            item.message = "; ".join([s.explain(s.bake.message)] + ranges)

    def cancel(self, index=None):
        """Cancels item `index` (pending: at once; baking: the CLI is stopped), or every
        pending item and the running one."""
        q = self.queue
        if q is None:
            return
        for i, item in enumerate(q.items):
            if index is not None and i != index:
                continue
            if item.state == "PENDING":
                item.state, item.message = "CANCELLED", "cancelled before it started"
            elif item.state == "BAKING" and i == self.index and self.session is not None:
                self.session.cancel()

    def wait(self, context, interval=0.05):
        while self.step(context):
            time.sleep(interval)


# The queue running now, if any (as operators._running: never saved in a .blend).
_running = {}


def running_queue():
    return _running.get("queue")


class NBRDF_OT_bake_all(bpy.types.Operator):
    """Bake every material of the selected objects (or the scene), one after another"""
    bl_idname = "nbrdf.bake_all"
    bl_label = "Bake All Materials"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        from .operators import running_session
        return running_queue() is None and running_session() is None

    def _fill(self, context):
        q = context.scene.nbrdf_queue
        pairs = gather(context, q.scope)
        if not pairs:
            self.report({"ERROR"}, "nbrdf: no mesh object with a material among the %s"
                        % ("selected objects" if q.scope == "SELECTED" else "scene's objects"))
            return None
        q.items.clear()
        for obj, mat in pairs:
            item = q.items.add()
            item.object_name, item.material_name = obj.name, mat.name
        q.index = 0
        return QueueRunner(context.scene)

    def _end(self, context):
        q = context.scene.nbrdf_queue
        counts = {}
        for item in q.items:
            counts[item.state] = counts.get(item.state, 0) + 1
        text = "nbrdf: %d done, %d failed, %d cancelled" % (
            counts.get("DONE", 0), counts.get("FAILED", 0), counts.get("CANCELLED", 0))
        self.report({"INFO"} if counts.get("DONE", 0) == len(q.items) else {"WARNING"}, text)
        return {"FINISHED"}

    def execute(self, context):
        # Blocking: for scripts and `blender -b`, where modal timers do not run.
        runner = self._fill(context)
        if runner is None:
            return {"CANCELLED"}
        _running["queue"] = runner
        try:
            runner.wait(context)
        finally:
            _running.pop("queue", None)
        return self._end(context)

    def invoke(self, context, event):
        runner = self._fill(context)
        if runner is None:
            return {"CANCELLED"}
        _running["queue"] = runner
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        runner = running_queue()
        if event.type == "ESC" and event.value == "PRESS" and runner is not None:
            runner.cancel()
            return {"RUNNING_MODAL"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        still = runner is not None and runner.step(context)
        _redraw(context)
        if still:
            return {"PASS_THROUGH"}
        self._stop(context)
        return self._end(context)

    def cancel(self, context):
        runner = running_queue()
        if runner is not None:
            runner.cancel()
            runner.wait(context)
        self._stop(context)

    def _stop(self, context):
        context.window_manager.event_timer_remove(self._timer)
        _running.pop("queue", None)
        _redraw(context)


class NBRDF_OT_queue_cancel(bpy.types.Operator):
    """Cancel the queue item (pending: it is skipped; baking: the bake stops, no file)"""
    bl_idname = "nbrdf.queue_cancel"
    bl_label = "Cancel Item"

    index: IntProperty(name="Item", default=-1, options={"SKIP_SAVE"},
                       description="Item to cancel (-1: the selected one)")
    all: BoolProperty(name="All", default=False, options={"SKIP_SAVE"},
                      description="Cancel every pending item and the running one")

    @classmethod
    def poll(cls, context):
        return running_queue() is not None

    def execute(self, context):
        runner = running_queue()
        if self.all:
            runner.cancel()
        else:
            runner.cancel(self.index if self.index >= 0 else context.scene.nbrdf_queue.index)
        _redraw(context)
        return {"FINISHED"}


class NBRDF_UL_queue(bpy.types.UIList):
    def draw_item(self, context, layout, data, item, icon, active_data, active_propname,
                  index=0, flt_flag=0):
        row = layout.row(align=True)
        row.label(text="%s / %s" % (item.object_name, item.material_name),
                  icon=ICONS.get(item.state, "DOT"))
        label = dict((s[0], s[1]) for s in STATES)[item.state]
        runner = running_queue()
        if item.state == "BAKING" and runner is not None and runner.session is not None:
            label = "%s %.0f %%" % (label, 100.0 * runner.session.progress)
        row.label(text=label)


def draw_queue(layout, context):
    q = context.scene.nbrdf_queue
    col = layout.column()
    col.use_property_split = True
    col.prop(q, "scope", expand=True)
    col.prop(q, "output")
    obj = context.active_object
    if obj is not None and obj.type == "MESH":
        col.prop_search(q, "uv_map", obj.data, "uv_layers")
    else:
        col.prop(q, "uv_map")
    col.prop(q, "read_material")
    col.prop(q, "bake_uv")
    row = layout.row(align=True)
    row.scale_y = 1.3
    row.operator("nbrdf.bake_all", icon="RENDER_STILL")
    if not q.items:
        return
    layout.template_list("NBRDF_UL_queue", "", q, "items", q, "index", rows=3)
    if running_queue() is not None:
        row = layout.row(align=True)
        row.operator("nbrdf.queue_cancel", text="Cancel Item", icon="X")
        op = row.operator("nbrdf.queue_cancel", text="Cancel All", icon="CANCEL")
        op.all = True
    if 0 <= q.index < len(q.items) and q.items[q.index].message:
        from .panels import label_wrapped
        item = q.items[q.index]
        label_wrapped(layout, context, item.message,
                      "ERROR" if item.state == "FAILED" else "INFO")


class NBRDF_PT_queue_view3d(bpy.types.Panel):
    bl_label = "Bake All Materials"
    bl_idname = "NBRDF_PT_queue_view3d"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "nbrdf"

    def draw(self, context):
        draw_queue(self.layout, context)


class NBRDF_PT_queue_material(bpy.types.Panel):
    bl_label = "Bake All Materials"
    bl_idname = "NBRDF_PT_queue_material"
    bl_parent_id = "NBRDF_PT_material"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "material"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        draw_queue(self.layout, context)


def _redraw(context):
    for window in context.window_manager.windows:
        for area in window.screen.areas:
            if area.type in {"PROPERTIES", "VIEW_3D", "NODE_EDITOR"}:
                area.tag_redraw()


data_classes = (NBRDF_QueueItem, NBRDF_QueueSettings)
classes = (NBRDF_OT_bake_all, NBRDF_OT_queue_cancel, NBRDF_UL_queue)
panel_classes = (NBRDF_PT_queue_view3d, NBRDF_PT_queue_material)


def register():
    for c in data_classes + classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.nbrdf_queue = PointerProperty(type=NBRDF_QueueSettings)


def register_panels():
    for c in panel_classes:
        bpy.utils.register_class(c)


def unregister_panels():
    for c in reversed(panel_classes):
        bpy.utils.unregister_class(c)


def unregister():
    runner = running_queue()
    if runner is not None:  # never leave a bake running behind a disabled add-on
        runner.cancel()
        runner.wait(bpy.context)
        _running.clear()
    del bpy.types.Scene.nbrdf_queue
    for c in reversed(data_classes + classes):
        bpy.utils.unregister_class(c)
