"""Add-on preferences: where the nbrdf executable and the model bundle are."""

import os

import bpy
from bpy.props import StringProperty

from . import locate

ADDON_DIR = os.path.dirname(os.path.abspath(__file__))


class NBRDF_Preferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    nbrdf_path: StringProperty(
        name="nbrdf Executable", subtype="FILE_PATH",
        description="The nbrdf command line tool; empty: next to the add-on, in its bin/ "
                    "folder, or on PATH")
    bundle_dir: StringProperty(
        name="Model Bundle", subtype="DIR_PATH",
        description="Folder of the model bundle (model.json and weights); empty: the add-on's "
                    "models/default, or models/default beside the executable")

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "nbrdf_path")
        layout.prop(self, "bundle_dir")
        exe, bundle, problem = resolve(self)
        col = layout.column(align=True)
        if problem:
            from .panels import label_wrapped
            label_wrapped(col, context, problem, "ERROR")
        else:
            col.label(text="nbrdf: " + exe, icon="CHECKMARK")
            col.label(text="bundle: " + bundle, icon="CHECKMARK")


def get(context):
    return context.preferences.addons[__package__].preferences


def resolve(prefs):
    """(nbrdf path, bundle dir, None) or (…, …, message saying what is missing)."""
    try:
        exe = locate.find_nbrdf(bpy.path.abspath(prefs.nbrdf_path), ADDON_DIR)
        bundle = locate.find_bundle(bpy.path.abspath(prefs.bundle_dir), ADDON_DIR, exe)
    except locate.NotFound as e:
        return None, None, str(e)
    problem = locate.check_runs(exe)
    if problem:
        return None, None, problem
    return exe, bundle, None


def register():
    bpy.utils.register_class(NBRDF_Preferences)


def unregister():
    bpy.utils.unregister_class(NBRDF_Preferences)
