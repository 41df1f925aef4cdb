"""Preview Object (issue 33): a UV sphere with a baked material, a scene camera and an
environment image render to an image of the requested size, lit where the object is and the
environment elsewhere; the turntable gives one frame per step as an image sequence; cancel
stops the render; an object without UVs, or a material not yet baked, is refused with a
message that says why; the exported camera and the environment's rotation show the world as
Cycles does (a tilted camera, an image that varies with azimuth and elevation)."""

import os
import sys

import bpy
import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import addon_testing as t  # noqa: E402

t.enable()
from nbrdf_bake import lookdev  # noqa: E402
from nbrdf_bake.inputs import SetupError  # noqa: E402

work = t.temp_dir()
W, H = 40, 24

for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)
bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12, radius=1.0)
obj = bpy.context.active_object
mat = bpy.data.materials.new("Look")
obj.data.materials.append(mat)
s = mat.nbrdf_bake
s.eta_value, s.alpha2_value = 1.5, 0.3
s.output = os.path.join(work, "{material}.exr")
s.preview = False
s.size_mode, s.size = "CUSTOM", (16, 16)
s.lookdev_size, s.lookdev_spp = (W, H), 2

# Not baked yet: refused.
try:
    lookdev.start_preview(bpy.context, obj)
    t.check("an unbaked material is refused", False)
except SetupError as e:
    t.check("unbaked: says to bake first (%s)" % e, "bake it first" in str(e))
t.check("bake finished", bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})

# A camera looking at the sphere from -Y (Blender's front), and a world image: bright
# (10) everywhere but a dark band, so the background is not black.
bpy.ops.object.camera_add(location=(0.0, -5.0, 0.0), rotation=(np.pi / 2, 0.0, 0.0))
bpy.context.scene.camera = bpy.context.active_object
bpy.context.view_layer.objects.active = obj
env = np.full((16, 32, 3), 2.0, np.float32)
env[6:10] = 0.5
path = os.path.join(work, "world.exr")
out = oiio.ImageOutput.create(path)
out.open(path, oiio.ImageSpec(32, 16, 3, "float"))
out.write_image(env)
out.close()
world = bpy.data.worlds.new("W")
world.use_nodes = True
node = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
node.image = bpy.data.images.load(path)
world.node_tree.links.new(node.outputs["Color"], world.node_tree.nodes["Background"].inputs[0])
bpy.context.scene.world = world

result = bpy.ops.nbrdf.preview_object()
t.check("preview finished (%s)" % result, result == {"FINISHED"})
im = s.lookdev_image
if t.check("preview image set", im is not None):
    t.check("size %s, expected %dx%d" % (tuple(im.size), W, H), tuple(im.size) == (W, H))
    px = np.array(im.pixels[:], np.float32).reshape(H, W, 4)[::-1]  # rows top to bottom
    centre, corner = px[H // 2, W // 2, :3], px[1, 1, :3]
    t.check("the object is lit: centre %s" % centre, centre.max() > 0.02)
    t.check("background is the environment: corner %s" % corner, corner.min() > 0.3)
    t.check("object differs from the background", np.abs(centre - corner).max() > 0.01)

# Turntable: 3 frames, an image sequence.
s.lookdev_turntable, s.lookdev_frames = True, 3
result = bpy.ops.nbrdf.preview_object()
t.check("turntable finished", result == {"FINISHED"})
im = s.lookdev_image
if t.check("turntable image", im is not None):
    t.check("a sequence", im.source == "SEQUENCE")
    folder = os.path.dirname(bpy.path.abspath(im.filepath))
    frames = sorted(f for f in os.listdir(folder) if f.endswith(".png"))
    t.check("three frames %s" % frames, len(frames) == 3)
s.lookdev_turntable = False

# Cancel: a long render stopped at once.
s.lookdev_size, s.lookdev_spp = (256, 256), 4096
preview = lookdev.start_preview(bpy.context, obj)
preview.cancel()
state = preview.wait()
t.check("cancelled (%s: %s)" % (state, preview.message), state == "cancelled")
s.lookdev_size, s.lookdev_spp = (W, H), 2

# No UVs: refused, naming the object.
while obj.data.uv_layers:
    obj.data.uv_layers.remove(obj.data.uv_layers[0])
try:
    lookdev.start_preview(bpy.context, obj)
    t.check("an object without UVs is refused", False)
except SetupError as e:
    t.check("no UVs: says so (%s)" % e, "has no UV map" in str(e) and obj.name in str(e))

# The camera and environment conventions against Cycles: the world seen through a tilted
# camera (no object in view) renders as Cycles renders it, within texture filtering.
import subprocess  # noqa: E402
from nbrdf_bake import lookdev_export  # noqa: E402

sc = bpy.context.scene
grad = np.zeros((32, 64, 3), np.float32)
grad[..., 0] = np.linspace(0.0, 1.0, 64)[None, :]
grad[..., 1] = np.linspace(1.0, 0.0, 32)[:, None]
grad[:, 40:44, 2] = 3.0
gpath = os.path.join(work, "gradient.exr")
out = oiio.ImageOutput.create(gpath)
out.open(gpath, oiio.ImageSpec(64, 32, 3, "float"))
out.write_image(grad)
out.close()
node.image = bpy.data.images.load(gpath)
node.interpolation = "Linear"
sc.camera.location, sc.camera.rotation_euler = (1.0, -2.0, 0.5), (1.3, 0.0, 0.6)
sc.camera.data.lens = 30
CW, CH = 64, 48
sc.render.engine, sc.cycles.samples, sc.cycles.use_denoising = "CYCLES", 4, False
sc.render.resolution_x, sc.render.resolution_y, sc.render.resolution_percentage = CW, CH, 100
sc.render.image_settings.file_format = "OPEN_EXR"
sc.render.filepath = os.path.join(work, "cycles.exr")
obj.hide_render = True
bpy.ops.render.render(write_still=True)
far = os.path.join(work, "far.obj")  # an object far behind the camera: only the world shows
with open(far, "w") as f:
    f.write("v 0 -100 0\nv 0.1 -100 0\nv 0 -100 0.1\nvt 0 0\nf 1/1 2/1 3/1\n")
mine = os.path.join(work, "nbrdf-world.exr")
argv = [t.NBRDF, "render", bpy.path.abspath(s.result.filepath), "--bundle", t.BUNDLE,
        "--mesh", far, "--env", gpath, "--env-rotation", str(lookdev_export.ENV_ROTATION_BASE),
        "--width", str(CW), "--height", str(CH), "--spp", "4", "-o", mine]
argv += lookdev_export.camera_args(sc, CW, CH)
t.check("nbrdf render of the world", subprocess.run(argv, capture_output=True).returncode == 0)
a = oiio.ImageBuf(sc.render.filepath).get_pixels(oiio.FLOAT)[..., :3]
b = oiio.ImageBuf(mine).get_pixels(oiio.FLOAT)[..., :3]
err = float(np.abs(a - b).max()) if a.shape == b.shape else 1e9
t.check("the world through the camera as Cycles shows it: max |difference| %.4g" % err,
        err < 0.02)
t.finish("test_lookdev")
