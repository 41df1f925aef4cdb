"""Run by scripts/blender-panel-screenshot.sh inside Blender with a window (Xvfb): bakes the
default cube's material through the add-on (from its Principled BSDF, a procedural roughness
baked through the UV map, verify on) and saves a screenshot of the material properties with
the nbrdf Latent Bake panel. Environment: NBRDF_SOURCE_DIR, NBRDF, NBRDF_BUNDLE, SHOT (PNG),
WORK (a folder for the bake)."""

import os
import sys

import addon_utils
import bpy

src = os.environ["NBRDF_SOURCE_DIR"]
sys.path.insert(0, os.path.join(src, "blender_addon"))
bpy.context.preferences.view.show_splash = False
addon_utils.enable("nbrdf_bake", default_set=True)
prefs = bpy.context.preferences.addons["nbrdf_bake"].preferences
prefs.nbrdf_path = os.environ["NBRDF"]
prefs.bundle_dir = os.environ["NBRDF_BUNDLE"]

cube = bpy.data.objects["Cube"]
mat = cube.active_material
mat.name = "Lacquered Copper"
tree = mat.node_tree
bsdf = tree.nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (0.95, 0.64, 0.54, 1.0)
bsdf.inputs["Metallic"].default_value = 1.0
bsdf.inputs["Clearcoat"].default_value = 1.0
bsdf.inputs["Clearcoat Roughness"].default_value = 0.2
noise = tree.nodes.new("ShaderNodeTexNoise")
ramp = tree.nodes.new("ShaderNodeMapRange")
ramp.inputs["To Min"].default_value, ramp.inputs["To Max"].default_value = 0.3, 0.7
tree.links.new(noise.outputs["Fac"], ramp.inputs["Value"])
tree.links.new(ramp.outputs["Result"], bsdf.inputs["Roughness"])
s = mat.nbrdf_bake
bpy.ops.nbrdf.use_material(material=mat.name)
s.bake_uv, s.verify = True, True
s.size_mode, s.size = "CUSTOM", (64, 64)
s.preview_size, s.preview_spp = 96, 4
s.output = os.path.join(os.environ["WORK"], "{material}.exr")
bpy.context.view_layer.objects.active = cube
bpy.ops.nbrdf.bake_latent(material=mat.name)  # blocking (execute), as from a script
if os.environ.get("LOOKDEV"):
    # Preview Object on the cube through the default scene's camera, under the sky (the
    # default world has no image); the rendered PNG is kept beside the screenshot.
    import shutil
    s.lookdev_size, s.lookdev_spp = (320, 240), 16
    bpy.ops.nbrdf.preview_object()  # blocking
    if s.lookdev_image is not None:
        s.lookdev_image.save_render(os.environ["LOOKDEV"])

# The big 3D viewport becomes the material properties, alone in the window.
window = bpy.context.window_manager.windows[0]
area = max(window.screen.areas, key=lambda a: a.width * a.height)
area.type = "PROPERTIES"
state = {"ticks": 0}


def scrolled_to_panel():
    region = next(r for r in area.regions if r.type == "WINDOW")
    with bpy.context.temp_override(window=window, area=area, region=region):
        # Past Preview and Surface (the Principled BSDF's sockets) to the bake panel.
        for _ in range(int(os.environ.get("SCROLL", "24"))):
            bpy.ops.view2d.scroll_down(deltay=40)


def shoot():
    try:
        return _shoot()
    except Exception as e:
        print("blender-panel-shot: %s" % e, file=sys.stderr)
        bpy.ops.wm.quit_blender()
        return None


def _shoot():
    state["ticks"] += 1
    if state["ticks"] == 1:  # its tabs exist once it has been drawn
        area.spaces[0].context = "MATERIAL"
        window.cursor_warp(2, 2)  # no tooltip under the cursor
    if state["ticks"] == 4:
        scrolled_to_panel()
    if state["ticks"] < 9:  # a few redraws: layout, scrolling, icon previews
        for a in window.screen.areas:
            a.tag_redraw()
        return 0.5
    with bpy.context.temp_override(window=window, area=area):
        bpy.ops.screen.screenshot_area(filepath=os.environ["SHOT"])
    bpy.ops.wm.quit_blender()
    return None


def give_up():  # never hang a script run: quit whatever happened
    bpy.ops.wm.quit_blender()


bpy.app.timers.register(give_up, first_interval=120.0)


bpy.app.timers.register(shoot, first_interval=1.0)
