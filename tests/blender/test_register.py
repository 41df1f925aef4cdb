"""The add-on enables, registers its classes and properties, finds (or clearly fails to find)
nbrdf and the bundle, and unregisters without leaving anything behind; twice."""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import addon_testing as t  # noqa: E402

CLASSES = ("NBRDF_PT_material", "NBRDF_PT_output", "NBRDF_PT_shader_editor",
           "NBRDF_OT_bake_latent",
           "NBRDF_OT_cancel_bake", "NBRDF_OT_bake_all", "NBRDF_OT_queue_cancel",
           "NBRDF_UL_queue", "NBRDF_PT_queue_view3d", "NBRDF_PT_queue_material")


def op_exists(name):
    try:
        getattr(bpy.ops.nbrdf, name).get_rna_type()
        return True
    except (KeyError, AttributeError):
        return False


def registered_state():
    types = [n for n in dir(bpy.types) if n.startswith("NBRDF_")]
    return (types, (hasattr(bpy.types.Material, "nbrdf_bake"),
                    hasattr(bpy.types.Scene, "nbrdf_queue")), op_exists("bake_latent"),
            op_exists("cancel_bake"), "nbrdf_bake" in bpy.context.preferences.addons)


for round_ in (1, 2):
    mod = t.enable()
    types, prop, bake_op, cancel_op, pref = registered_state()
    for name in CLASSES:
        t.check("round %d: bpy.types.%s registered" % (round_, name), name in types)
    t.check("round %d: Material.nbrdf_bake, Scene.nbrdf_queue" % round_, all(prop))
    t.check("round %d: operators" % round_, bake_op and cancel_op)
    t.check("round %d: preferences" % round_, pref)
    t.check("bl_info says Blender 3.4", tuple(mod.bl_info["blender"]) == (3, 4, 0))
    mat = bpy.data.materials.new("m%d" % round_)
    t.check("settings on a material", mat.nbrdf_bake.roughness == "PERCEPTUAL")
    classes = [c for m in (mod.operators, mod.panels, mod.properties, mod.queue)
               for c in m.classes]
    classes += list(mod.queue.data_classes + mod.queue.panel_classes)
    classes.append(mod.preferences.NBRDF_Preferences)
    t.check("round %d: every class registered" % round_, all(c.is_registered for c in classes))

    t.disable()
    types, prop, bake_op, cancel_op, pref = registered_state()
    t.check("round %d: no NBRDF_ types after unregister: %s" % (round_, types), not types)
    t.check("round %d: no Material.nbrdf_bake, Scene.nbrdf_queue after unregister" % round_,
            not any(prop))
    t.check("round %d: no operators after unregister" % round_, not (bake_op or cancel_op))
    t.check("round %d: not in preferences" % round_, not pref)
    t.check("round %d: classes report unregistered" % round_,
            not any(c.is_registered for c in classes))

# Locating nbrdf and the bundle: set paths, automatic discovery, clear messages.
t.enable(configure=False)
from nbrdf_bake import preferences  # noqa: E402

prefs = bpy.context.preferences.addons["nbrdf_bake"].preferences
root = t.temp_dir()
os.makedirs(os.path.join(root, "bin"))
os.symlink(t.NBRDF, os.path.join(root, "bin", "nbrdf"))
saved_path = os.environ.get("PATH", "")

os.environ["PATH"] = root  # no nbrdf there
exe, bundle, problem = preferences.resolve(prefs)
t.check("not found: message names the preferences: %s" % problem,
        problem and "not found" in problem and "Preferences" in problem)

os.environ["PATH"] = os.path.join(root, "bin")
exe, bundle, problem = preferences.resolve(prefs)
t.check("bundle not found beside the executable: %s" % problem,
        problem and "model bundle not found" in problem and "bundle init" in problem)
os.makedirs(os.path.join(root, "models"))
os.symlink(t.BUNDLE, os.path.join(root, "models", "default"))
exe, bundle, problem = preferences.resolve(prefs)
t.check("found on PATH with ../models/default: %s" % problem, problem is None)
t.check("executable from PATH", exe == os.path.join(root, "bin", "nbrdf"))
t.check("bundle beside it", bundle == os.path.join(root, "models", "default"))

prefs.nbrdf_path = os.path.join(root, "no-such-nbrdf")
exe, bundle, problem = preferences.resolve(prefs)
t.check("a wrong path set is an error naming it: %s" % problem,
        problem and "no-such-nbrdf" in problem)
prefs.nbrdf_path = t.NBRDF
prefs.bundle_dir = root
exe, bundle, problem = preferences.resolve(prefs)
t.check("a bundle folder without model.json is an error: %s" % problem,
        problem and "model.json" in problem)
os.environ["PATH"] = saved_path
t.disable()
t.finish("test_register")
