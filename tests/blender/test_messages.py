"""What the add-on says and stores in the user's terms: a CLI error about an input the
add-on baked through the UV map names the material, socket and node rather than the
temporary file; the result image of an output asked for relative to the .blend (//) is
stored relative, and maps on disk are recorded relative to the output; a copied nbrdf that cannot run on this machine (missing shared libraries)
is said so plainly, in the panel's and the preferences' message."""

import os
import stat
import subprocess
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import addon_testing as t  # noqa: E402

t.enable()
from nbrdf_bake import preferences  # noqa: E402

work = t.temp_dir()
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(work, "scene.blend"))
cube = bpy.data.objects["Cube"]

mat = bpy.data.materials.new("Varnish")
mat.use_nodes = True
bsdf = mat.node_tree.nodes["Principled BSDF"]
bsdf.inputs["Clearcoat Roughness"].default_value = 0.3
cube.data.materials.clear()
cube.data.materials.append(mat)
s = mat.nbrdf_bake
s.size_mode, s.size = "CUSTOM", (8, 8)
s.preview = False
bpy.ops.nbrdf.use_material(material=mat.name)

# 1. Relative output: the result image's path is relative too.
s.output = "//latent/{material}.exr"
t.check("bake", bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})
t.check("written beside the .blend", os.path.isfile(os.path.join(work, "latent", "Varnish.exr")))
t.check("result stored relative: %s" % (s.result and s.result.filepath),
        s.result is not None and s.result.filepath == "//latent/Varnish.exr")
s.output = os.path.join(work, "abs", "{material}.exr")
t.check("bake (absolute)", bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})
t.check("an absolute output stays absolute: %s" % s.result.filepath,
        s.result.filepath == os.path.join(work, "abs", "Varnish.exr"))

# Maps on disk are recorded relative to the output in the texture's parameterSources.
os.makedirs(os.path.join(work, "textures"))
rust = bpy.data.images.new("rust", 4, 4)
rust.filepath_raw = os.path.join(work, "textures", "rust.png")
rust.file_format = "PNG"
rust.save()
rust = bpy.data.images.load(os.path.join(work, "textures", "rust.png"))
s.r0_source, s.r0_image = "IMAGE", rust
s.output = "//latent/{material}.exr"
t.check("bake with a map on disk", bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})
info = subprocess.run([t.NBRDF, "info", os.path.join(work, "latent", "Varnish.exr")],
                      capture_output=True, text=True).stdout
t.check("the map recorded relative to the output: %s" % info, "r0=../textures/rust.png" in info)
s.r0_source = "MATERIAL"

# 2. A negative roughness from a node (baked through the UV map): the CLI's message about
# its temporary file names the user's node and material instead.
neg = mat.node_tree.nodes.new("ShaderNodeMath")
neg.name = "Wear Mask"
neg.operation = "SUBTRACT"
neg.inputs[0].default_value, neg.inputs[1].default_value = 0.0, 0.5
mat.node_tree.links.new(neg.outputs[0], bsdf.inputs["Roughness"])
s.bake_uv = True
bpy.context.view_layer.objects.active = cube
try:
    bpy.ops.nbrdf.bake_latent(material=mat.name)
    message = None
except RuntimeError as e:
    message = str(e)
t.check("the failure names the node and material: %s" % message, message is not None
        and "the UV bake of material 'Varnish', input 'Roughness' from node 'Wear Mask' "
            "(Math)" in message and "negative" in message and "_alpha2.exr" not in message)

# 3. An nbrdf that the loader refuses: what it lacks, said where the user looks.
fake = os.path.join(work, "nbrdf")
with open(fake, "w") as f:
    f.write("#!/bin/sh\necho 'nbrdf: error while loading shared libraries: "
            "libOpenImageIO.so.2.4: cannot open shared object file' >&2\nexit 127\n")
os.chmod(fake, os.stat(fake).st_mode | stat.S_IXUSR)
prefs = bpy.context.preferences.addons["nbrdf_bake"].preferences
prefs.nbrdf_path = fake
exe, bundle, problem = preferences.resolve(prefs)
t.check("a copied nbrdf that cannot run: %s" % problem, problem is not None
        and "does not run here" in problem and "libOpenImageIO.so.2.4" in problem
        and "Preferences" in problem)
try:
    bpy.ops.nbrdf.bake_latent(material=mat.name)
    message = None
except RuntimeError as e:
    message = str(e)
t.check("the bake button says it too: %s" % message, message and "does not run here" in message)
prefs.nbrdf_path = t.NBRDF
t.check("the real one runs", preferences.resolve(prefs)[2] is None)

t.disable()
t.finish("test_messages")
