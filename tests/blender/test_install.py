"""The zip from scripts/package-blender-addon.sh (with nbrdf in bin/ and a bundle in
models/default) installs through Blender's add-on installer, finds both with no setting,
and bakes constants with the operator. Needs $NBRDF_ADDON_ZIP and $BLENDER_USER_SCRIPTS
(set by run_blender.sh); the add-on comes from the zip, not from the source tree."""

import os
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import addon_testing as t  # noqa: E402

zip_path = os.environ["NBRDF_ADDON_ZIP"]
user_scripts = os.environ["BLENDER_USER_SCRIPTS"]
t.check("addon_install", bpy.ops.preferences.addon_install(filepath=zip_path) == {"FINISHED"})
errors = []
mod = addon_utils.enable("nbrdf_bake", default_set=True, handle_error=errors.append)
t.check("enabled from the zip: %s" % errors, mod is not None and not errors)
if mod is not None:
    where = os.path.dirname(os.path.realpath(mod.__file__))
    t.check("installed under BLENDER_USER_SCRIPTS: %s" % where,
            where.startswith(os.path.realpath(user_scripts)))
    from nbrdf_bake import preferences  # noqa: E402

    exe, bundle, problem = preferences.resolve(preferences.get(bpy.context))
    t.check("nbrdf found in the add-on's bin/: %s" % (problem or exe),
            problem is None and exe == os.path.join(where, "bin", "nbrdf"))
    t.check("bundle found in the add-on's models/default: %s" % bundle,
            problem is None and bundle == os.path.join(where, "models", "default"))

    mat = bpy.data.materials.new("Constants")
    work = t.temp_dir()
    mat.nbrdf_bake.output = os.path.join(work, "c.exr")
    t.check("bake of constants", bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})
    t.check("c.exr written", os.path.isfile(os.path.join(work, "c.exr")))
    t.disable()
t.finish("test_install")
