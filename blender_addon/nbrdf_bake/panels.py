"""Material Properties > nbrdf Latent Bake: the six parameters, options, the button."""

import bpy

from . import operators, preferences
from .params import PARAMS


class NBRDF_PT_material(bpy.types.Panel):
    bl_label = "nbrdf Latent Bake"
    bl_idname = "NBRDF_PT_material"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "material"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        return context.material is not None

    def draw(self, context):
        layout = self.layout
        s = context.material.nbrdf_bake
        for p in PARAMS:
            row = layout.row(align=True)
            row.label(text=p.label)
            row.prop(s, p.key + "_source", text="", expand=False)
            if getattr(s, p.key + "_source") == "IMAGE":
                layout.template_ID(s, p.key + "_image", new="image.new", open="image.open")
            else:
                layout.prop(s, p.key + "_value", text="")
        layout.separator()
        col = layout.column()
        col.use_property_split = True
        col.prop(s, "roughness")
        col.prop(s, "colour_maps")
        col.prop(s, "eta_range")
        col.prop(s, "sigma_t_range")
        col.prop(s, "range_policy")

        session = operators.running_session()
        if session is not None:
            box = layout.box()
            doing = "Baking" if session.stage == "bake" else "Rendering a preview of"
            box.label(text="%s %s: %.0f %%" % (doing, session.material_name,
                                               100.0 * session.progress), icon="TIME")
            box.operator("nbrdf.cancel_bake", icon="CANCEL")
            return
        exe, bundle, problem = preferences.resolve(preferences.get(context))
        if problem:
            layout.label(text=problem, icon="ERROR")
        row = layout.row()
        row.scale_y = 1.4
        row.enabled = problem is None
        row.operator("nbrdf.bake_latent", icon="RENDER_STILL")
        if s.result is not None:
            layout.label(text="Result: " + s.result.name, icon="IMAGE_DATA")
        if s.preview_image is not None:
            layout.label(text="Preview: " + s.preview_image.name, icon="SHADING_RENDERED")


class NBRDF_PT_output(bpy.types.Panel):
    bl_label = "Output"
    bl_parent_id = "NBRDF_PT_material"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "material"

    def draw(self, context):
        col = self.layout.column()
        col.use_property_split = True
        s = context.material.nbrdf_bake
        col.prop(s, "output")
        col.prop(s, "storage")
        col.prop(s, "mip_levels")
        col.prop(s, "tile")
        col.prop(s, "preview")
        sub = col.column()
        sub.enabled = s.preview
        sub.prop(s, "preview_size")
        sub.prop(s, "preview_spp")


classes = (NBRDF_PT_material, NBRDF_PT_output)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
