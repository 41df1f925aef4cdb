"""Material Properties > nbrdf Latent Bake (with an Output sub-panel), and the same in the
Shader Editor's sidebar (tab nbrdf): the six parameters, options, the button."""

import textwrap

import bpy

from . import material_inputs, operators, preferences, queue, tiled_images
from .params import PARAMS


def draw_parameters(layout, s, material=None):
    row = layout.row()
    row.operator("nbrdf.use_material", icon="MATERIAL")
    reading = _reading(material) if any(
        getattr(s, p.key + "_source") == "MATERIAL" for p in PARAMS) else None
    for p in PARAMS:
        row = layout.row(align=True)
        row.label(text=p.label)
        row.prop(s, p.key + "_source", expand=True)
        source = getattr(s, p.key + "_source")
        if source == "IMAGE":
            layout.template_ID(s, p.key + "_image", new="image.new", open="image.open")
        elif source == "MATERIAL":
            layout.label(text=_describe(reading, p.key), icon="NODE")
        else:
            layout.prop(s, p.key + "_value", text="")
    layout.separator()
    col = layout.column()
    col.use_property_split = True
    for name in ("roughness", "colour_maps", "eta_range", "sigma_t_range", "range_policy",
                 "size_mode"):
        col.prop(s, name)
    sub = col.column()
    sub.prop(s, "size")
    col.prop(s, "resample")
    col.prop(s, "accuracy")
    sub = col.column()
    sub.active = s.accuracy != "FAST"
    sub.prop(s, "budget")
    if s.accuracy == "AUTO":
        col.prop(s, "max_error")
    if s.accuracy == "COMPACT":
        col.prop(s, "compact_channels")
    col.prop(s, "bake_uv")
    col.prop(s, "verify")


def _reading(material):
    try:
        return material_inputs.read(material)[0]
    except (material_inputs.MaterialError, AttributeError) as e:
        return str(e)


def _describe(reading, key):
    if isinstance(reading, str) or reading is None:
        return reading or "no material"
    r = reading[key]
    if r.kind == "value":
        return "%s: %s" % (r.socket, ", ".join("%.3g" % v for v in r.value))
    if r.kind == "image":
        return "%s: image %s" % (r.socket, r.value.name)
    return "%s: node %s (Bake Through UV Map)" % (r.socket, r.value.links[0].from_node.name)


def draw_output(layout, s):
    col = layout.column()
    col.use_property_split = True
    for name in ("output", "storage", "mip_levels", "tile", "preview"):
        col.prop(s, name)
    sub = col.column()
    sub.enabled = s.preview
    sub.prop(s, "preview_size")
    sub.prop(s, "preview_spp")
    col.prop(s, "farm_plan")


def draw_bake(layout, context, s):
    session = operators.running_session()
    if session is not None:
        box = layout.box()
        if session.cancelling:
            box.label(text="Cancelling %s …" % session.material_name, icon="CANCEL")
            return
        doing = {"bake": "Baking", "verify": "Verifying",
                 "preview": "Rendering a preview of"}[session.stage]
        step = session.step_name
        step = " (%s)" % step if step and step != session.stage else ""
        box.label(text="%s %s%s: %.0f %%" % (doing, session.material_name, step,
                                             100.0 * session.progress), icon="TIME")
        if session.tile_text:  # a tile set: the line above is the set's, this the tile's
            box.label(text=session.tile_text, icon="UV")
        box.operator("nbrdf.cancel_bake", icon="CANCEL")
        draw_ranges(layout, context, session.ranges)
        return
    exe, bundle, problem = preferences.resolve(preferences.get(context))
    if problem:
        label_wrapped(layout, context, problem, "ERROR")
    row = layout.row()
    row.scale_y = 1.4
    row.enabled = problem is None
    row.operator("nbrdf.bake_latent", icon="RENDER_STILL")
    sub = row.row()
    sub.scale_x = 0.7
    sub.enabled = problem is None and has_tiles(s)
    sub.operator("nbrdf.write_farm_plan", text="Farm Plan", icon="NETWORK_DRIVE")
    draw_ranges(layout, context, [l for l in s.range_report.split("\n") if l])
    draw_results(layout, s)
    if s.result is not None:
        draw_lookdev(layout, s)
    if s.farm_report:
        label_wrapped(layout, context, s.farm_report, "NETWORK_DRIVE")


def has_tiles(s):
    """Whether an input is a tiled image (the bake is a tile set, which a farm plan takes)."""
    reading = None
    for p in PARAMS:
        source = getattr(s, p.key + "_source")
        image = getattr(s, p.key + "_image") if source == "IMAGE" else None
        if source == "MATERIAL":
            if reading is None:
                reading = _reading(s.id_data)
            r = reading.get(p.key) if isinstance(reading, dict) else None
            image = r.value if r is not None and r.kind == "image" else None
        if tiled_images.is_tiled(image):
            return True
    return False


def draw_ranges(layout, context, lines):
    """The bake's range report: each input outside the model's trained range, in the units
    of the panel (perceptual roughness, IOR), before the bake's work starts."""
    if not lines:
        return
    box = layout.box()
    box.label(text="Outside the model's trained range:", icon="ERROR")
    for line in lines:
        label_wrapped(box, context, line, "DOT")


def draw_results(layout, s):
    if s.result is None:
        return
    box = layout.box()
    tiled = s.result.source == "TILED"
    box.label(text="Latent texture: " + s.result.name + (
        " (%d tiles)" % len(s.result.tiles) if tiled else ""), icon="IMAGE_DATA")
    if s.accuracy_result:
        box.label(text=s.accuracy_result, icon="INFO")
    if s.verify_texels:
        box.label(text="Verify (%d texels): median lobe error %.1f %%, worst %.1f %%"
                  % (s.verify_texels, s.verify_median, s.verify_worst), icon="CHECKMARK")
    im = s.preview_image
    if im is not None:
        im.preview_ensure()
        box.label(text="Preview render", icon="SHADING_RENDERED")
        box.template_icon(icon_value=im.preview.icon_id, scale=6.0)


def draw_lookdev(layout, s):
    """Preview Object: the baked material on the active object (lookdev.py)."""
    from .lookdev import running_preview
    box = layout.box()
    box.label(text="Preview Object", icon="SHADING_RENDERED")
    row = box.row(align=True)
    row.prop(s, "lookdev_size", text="")
    row.prop(s, "lookdev_spp")
    row = box.row(align=True)
    row.prop(s, "lookdev_turntable")
    sub = row.row()
    sub.enabled = s.lookdev_turntable
    sub.prop(s, "lookdev_frames")
    preview = running_preview()
    if preview is not None:
        box.label(text="Rendering frame %d of %d: %d %%" % (
            preview.frame + 1, preview.frames, int(100 * preview.progress)))
        box.operator("nbrdf.cancel_preview", icon="CANCEL")
    else:
        row = box.row()
        row.enabled = s.result is not None
        row.operator("nbrdf.preview_object", icon="RENDER_STILL")
    im = s.lookdev_image
    if im is not None:
        im.preview_ensure()
        box.template_icon(icon_value=im.preview.icon_id, scale=8.0)
        box.operator("nbrdf.show_preview", icon="IMAGE").image = im.name


def label_wrapped(layout, context, text, icon):
    """Labels do not wrap; a long message would be cut at the panel's edge."""
    # About 10 pixels a character at scale 1, less the icon's width (measured in 3.4).
    px = 10 * context.preferences.view.ui_scale
    chars = max(20, int((context.region.width - 4 * px) / px))
    col = layout.column(align=True)
    for i, line in enumerate(textwrap.wrap(text, chars)):
        col.label(text=line, icon=icon if i == 0 else "BLANK1")


class NBRDF_PT_material(bpy.types.Panel):
    bl_label = "nbrdf Latent Bake"
    bl_idname = "NBRDF_PT_material"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        return context.material is not None

    def draw(self, context):
        s = context.material.nbrdf_bake
        draw_parameters(self.layout, s, context.material)
        draw_bake(self.layout, context, s)


class NBRDF_PT_output(bpy.types.Panel):
    bl_label = "Output"
    bl_parent_id = "NBRDF_PT_material"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "material"

    def draw(self, context):
        draw_output(self.layout, context.material.nbrdf_bake)


class NBRDF_PT_shader_editor(bpy.types.Panel):
    bl_label = "Latent Bake"
    bl_idname = "NBRDF_PT_shader_editor"
    bl_space_type = "NODE_EDITOR"
    bl_region_type = "UI"
    bl_category = "nbrdf"

    @classmethod
    def poll(cls, context):
        space = context.space_data
        return (space is not None and space.tree_type == "ShaderNodeTree"
                and context.material is not None)

    def draw(self, context):
        s = context.material.nbrdf_bake
        draw_parameters(self.layout, s, context.material)
        self.layout.separator()
        draw_output(self.layout, s)
        draw_bake(self.layout, context, s)


classes = (NBRDF_PT_material, NBRDF_PT_output, NBRDF_PT_shader_editor)


# Blender draws a region's panels of equal bl_order in registration order, and the built-in
# ones register before any add-on: ours would come last. Re-registering the material
# Settings panel and those under it (each after its children were taken off) puts ours above
# Settings, below Surface and Volume, where the bake's inputs are.
_BELOW = ("EEVEE_MATERIAL_PT_settings", "CYCLES_MATERIAL_PT_settings", "MATERIAL_PT_lineart",
          "EEVEE_MATERIAL_PT_viewport_settings", "MATERIAL_PT_viewport")


def _move_below_ours():
    for name in _BELOW:
        cls = getattr(bpy.types, name, None)
        if cls is None or not isinstance(cls, type):
            continue
        children = [c for c in _registered_panels() if getattr(c, "bl_parent_id", "") == name]
        try:
            for c in children:
                bpy.utils.unregister_class(c)
            bpy.utils.unregister_class(cls)
            bpy.utils.register_class(cls)
            for c in children:
                bpy.utils.register_class(c)
        except (RuntimeError, ValueError) as e:  # never fail the add-on over panel order
            print("nbrdf: could not move panel %s below the bake panel: %s" % (name, e))


def _registered_panels():
    out, todo = [], list(bpy.types.Panel.__subclasses__())
    while todo:
        c = todo.pop()
        todo += c.__subclasses__()
        if getattr(c, "is_registered", False):
            out.append(c)
    return out


def register():
    for c in classes:
        bpy.utils.register_class(c)
    queue.register_panels()  # under NBRDF_PT_material, so after it
    _move_below_ours()


def unregister():
    queue.unregister_panels()
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
