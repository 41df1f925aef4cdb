"""UDIM tile sets (docs/BLENDER.md, "UDIM tile sets"): a material whose Roughness is a 2-tile
Image Texture (32 x 32 PNG tiles on disk) bakes a tile set latent.<UDIM>.exr, loaded back as
a tiled image with both tiles, wired like a single result, stored relative to the .blend;
tile 1002 equals, byte for byte, the CLI's own bake of the same set; a re-run skips both
tiles; tiles generated in Blender (never saved) bake too; a set whose tiles disagree gets the
CLI's error naming the user's node; a cancelled set's message keeps its finished tiles; Write
Farm Plan writes a plan naming both tiles, with its submit.sh."""

import filecmp
import json
import os
import subprocess
import sys
import time
import types

import bpy
import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import addon_testing as t  # noqa: E402

t.enable()
from nbrdf_bake import operators, panels  # noqa: E402
from nbrdf_bake.process import BakeProcess  # noqa: E402
from nbrdf_bake.session import NODE_NAME, Session  # noqa: E402

work = t.temp_dir()
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(work, "scene.blend"))
tex = os.path.join(work, "tex")
os.makedirs(tex)
N = 32


def write_png(path, pixels):
    o = oiio.ImageOutput.create(path)
    o.open(path, oiio.ImageSpec(N, N, pixels.shape[2], oiio.UINT8))
    o.write_image(pixels)
    o.close()


# Three grey levels per tile (few distinct texels: the bake is quick), different per tile.
for tile, level in ((1001, 60), (1002, 150)):
    px = (np.arange(N * N).reshape(N, N, 1) % 3 * 20 + level).astype(np.uint8)
    write_png(os.path.join(tex, "rough.%d.png" % tile), px)
rough = bpy.data.images.load(os.path.join(tex, "rough.1001.png"))
rough.source = "TILED"
rough.colorspace_settings.name = "Non-Color"
t.check("the test's image is tiled: %s %s" % (rough.filepath, [x.number for x in rough.tiles]),
        [x.number for x in rough.tiles] == [1001, 1002])

mat = bpy.data.materials.new("Udim")
mat.use_nodes = True
nodes = mat.node_tree.nodes
bsdf = nodes["Principled BSDF"]
bsdf.inputs["Clearcoat Roughness"].default_value = 0.25
bsdf.inputs["IOR"].default_value = 1.5
bsdf.inputs["Base Color"].default_value = (0.5, 0.5, 0.5, 1.0)
bsdf.inputs["Metallic"].default_value = 1.0
node = nodes.new("ShaderNodeTexImage")
node.name = "Rough Tiles"
node.image = rough
mat.node_tree.links.new(node.outputs["Color"], bsdf.inputs["Roughness"])
s = mat.nbrdf_bake
t.check("Use Material", bpy.ops.nbrdf.use_material(material=mat.name) == {"FINISHED"})
s.albedo_value, s.sigma_t_value = (0.5, 0.5, 0.5), 2.0
s.output = "//latent/{material}.exr"
latent = os.path.join(work, "latent")

# 1. The operator bakes the set: one texture per tile, loaded as one tiled image.
before = t.bake_temp_dirs()
t.check("bake finished", bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})
files = sorted(os.listdir(latent))
t.check("one texture per tile: %s" % files, files == ["Udim.1001.exr", "Udim.1002.exr"])
t.check("temporary inputs removed", t.bake_temp_dirs() == before)
img = s.result
t.check("result is tiled", img is not None and img.source == "TILED")
if img is not None:
    t.check("both tiles: %s" % [x.number for x in img.tiles],
            [x.number for x in img.tiles] == [1001, 1002])
    t.check("tile sizes", all(tuple(x.size) == (N, N) for x in img.tiles))
    t.check("relative path, as the output: %s" % img.filepath,
            img.filepath == "//latent/Udim.<UDIM>.exr")
    t.check("result is MULTILAYER: %s" % img.type, img.type == "MULTILAYER")
    t.check("wired like a single result", nodes.get(NODE_NAME) is not None
            and nodes[NODE_NAME].image == img)

# 2. The CLI's own bake of the same set, from a folder beside it (the same relative paths).
ref = os.path.join(work, "ref")
os.makedirs(ref)
cli = subprocess.run(
    [t.NBRDF, "bake", "--bundle", t.BUNDLE, "--alpha1", "0.25", "--eta", "1.5",
     "--alpha2", "../tex/rough.<UDIM>.png", "--r0", "0.5", "--albedo", "0.5", "--sigma-t", "2",
     "--roughness", "perceptual", "-o", "Udim.<UDIM>.exr"], cwd=ref, capture_output=True,
    text=True)
t.check("CLI bake of the set: %s" % cli.stderr, cli.returncode == 0)
t.check("tile 1002: add-on == CLI, byte for byte",
        filecmp.cmp(os.path.join(latent, "Udim.1002.exr"), os.path.join(ref, "Udim.1002.exr"),
                    shallow=False))

# 3. A re-run resumes: both tiles are up to date and left alone. Verify checks the set.
mtimes = [os.stat(os.path.join(latent, f)).st_mtime_ns for f in files]
s.verify = True
session = Session.start(bpy.context, mat)
t.check("re-run: done", session.wait() == "done")
t.check("verify of the set: %s" % (session.verify and session.verify.message),
        session.verify is not None and session.verify.state == "done"
        and s.verify_texels > 0 and s.verify_median >= 0.0)
s.verify = False
r = session.bake.result or {}
t.check("re-run: both tiles skipped: %s" % r, r.get("tiles") == 2 and r.get("skipped") == 2)
t.check("re-run: files untouched",
        mtimes == [os.stat(os.path.join(latent, f)).st_mtime_ns for f in files])
t.check("re-run: the report says so: %s" % session.report()[1],
        "2 skipped" in session.report()[1])


# The panel while a set bakes (over a recording layout: `blender -b` draws no panel): the
# set's share, then the tile's own line.
class Layout:
    def __init__(self, calls):
        self.calls = calls

    def __getattr__(self, name):
        def call(*args, **kwargs):
            self.calls.append((name, args, kwargs))
            return Layout(self.calls)
        return call


def labels(draw, *args):
    calls = []
    draw(Layout(calls), *args)
    return [c[2].get("text", "") for c in calls if c[0] == "label"]


ctx = types.SimpleNamespace(preferences=bpy.context.preferences,
                            region=types.SimpleNamespace(width=400))
session = Session.start(bpy.context, mat)
session.bake._event('{"event":"progress","stage":"bake","done":16,"total":32,"tile":1002,'
                    '"tile_index":2,"tiles":2}')
operators._running["session"] = session
shown = labels(panels.draw_bake, ctx, s)
operators._running.clear()
t.check("panel: the set's progress and the tile's: %s" % shown,
        any("Udim: 75 %" in x for x in shown) and "tile 1002 (2/2): 50 %" in shown)
session.wait()
shown = labels(panels.draw_results, s)
t.check("panel: the tiled result: %s" % shown, any("(2 tiles)" in x for x in shown))
t.check("panel: Farm Plan enabled for a tile set", panels.has_tiles(s))
t.check("panel: not for single images", not panels.has_tiles(
    bpy.data.materials.new("Single").nbrdf_bake))

# Packed tiles: their packed bytes are the input; the same latents as from the files.
rough.pack()
t.check("the test's image is packed: %d files" % len(rough.packed_files),
        len(rough.packed_files) == 2)
s.output = "//packed/{material}.exr"
t.check("packed tiles: bake finished",
        bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})
a = oiio.ImageBuf(os.path.join(latent, "Udim.1002.exr")).get_pixels(oiio.FLOAT)
b = oiio.ImageBuf(os.path.join(work, "packed", "Udim.1002.exr")).get_pixels(oiio.FLOAT)
t.check("packed tiles: the same latents", a is not None and b is not None
        and np.array_equal(a, b))
rough.unpack(method="USE_ORIGINAL")

# 4. Tiles that exist only in Blender (a generated float image, two filled tiles) for the
# coat roughness, beside the roughness tiles on disk.
def generated_tiles(name, numbers, value):
    im = bpy.data.images.new(name, N, N, float_buffer=True, tiled=True)
    im.colorspace_settings.name = "Non-Color"
    im.pixels.foreach_set(np.full(N * N * 4, value, np.float32))  # tile 1001
    with bpy.context.temp_override(edit_image=im):
        for n in numbers[1:]:
            bpy.ops.image.tile_add(number=n, fill=True, color=(value, value, value, 1.0),
                                   width=N, height=N, float=True)
    return im


coat = nodes.new("ShaderNodeTexImage")
coat.name = "Coat Tiles"
coat_tiles = generated_tiles("coat", [1001, 1002], 0.4)
coat.image = coat_tiles
mat.node_tree.links.new(coat.outputs["Color"], bsdf.inputs["Clearcoat Roughness"])
s.output = "//generated/{material}.exr"
t.check("generated tiles: bake finished",
        bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})
t.check("generated tiles: both written",
        sorted(os.listdir(os.path.join(work, "generated"))) == files)
t.check("generated tiles: temporary inputs removed", t.bake_temp_dirs() == before)
# Their temporary files are new each time, stamped with a time from their bytes: a re-run
# skips both tiles, and a tile painted since is baked again.
session = Session.start(bpy.context, mat)
t.check("generated tiles, re-run: done", session.wait() == "done")
r = session.bake.result or {}
t.check("generated tiles, re-run: both skipped: %s" % r, r.get("skipped") == 2)
px = np.full(N * N * 4, 0.5, np.float32)
coat.image.pixels.foreach_set(px)  # tile 1001 painted
session = Session.start(bpy.context, mat)
t.check("generated tiles, painted: done", session.wait() == "done")
r = session.bake.result or {}
t.check("generated tiles, painted: 1001 baked, 1002 skipped: %s" % session.bake.finished,
        [(e.get("tile"), e.get("status")) for e in session.bake.finished]
        == [(1001, "baked"), (1002, "skipped")])
t.check("painted tiles: still unsaved after the bake (Blender offers to save them)",
        coat.image.is_dirty)

# 5. Tiles that disagree (coat 1001 and 1003, roughness 1001 and 1002): the CLI's error,
# with the user's node named.
coat.image = generated_tiles("coat gap", [1001, 1003], 0.4)
s.output = "//gap/{material}.exr"
try:
    bpy.ops.nbrdf.bake_latent(material=mat.name)
    message = None
except RuntimeError as e:
    message = str(e)
t.check("disagreeing tiles: the CLI's error: %s" % message,
        message is not None and "has no tile" in message)
t.check("disagreeing tiles: the node named", message is not None and "'Coat Tiles'" in message
        and "'Rough Tiles'" in message)
t.check("disagreeing tiles: no file", not os.listdir(os.path.join(work, "gap")))
mat.node_tree.links.remove(coat.outputs["Color"].links[0])

# A single image beside the tiles applies to every tile (the CLI's rule): a 16 x 16 base
# colour, resampled to each tile's 32 x 32 (Resample Maps is on).
base = bpy.data.images.new("base", 16, 16)
base.pixels.foreach_set(np.tile(np.array([0.9, 0.6, 0.3, 1.0], np.float32), 16 * 16))
s.r0_source, s.r0_image = "IMAGE", base
s.output = "//mixed/{material}.exr"
t.check("tiles and a single image: bake finished",
        bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})
for f in files:
    path = os.path.join(work, "mixed", f)
    spec = oiio.ImageInput.open(path).spec() if os.path.isfile(path) else None
    t.check("tiles and a single image: %s 32 x 32, rgb" % f, spec is not None
            and (spec.width, spec.height) == (N, N) and "latent.L00.B" in spec.channelnames)
s.r0_source = "MATERIAL"

# 6. A cancelled set: tile 1001 (32 x 32) done, tile 1002 (256 x 1024 distinct float texels,
# four bands of rows) cancelled after its first progress line: 1001 stays, 1002 has no file,
# no temporary file is left, the message says so. Then the CLI's events replayed.
wear = os.path.join(tex, "wear")
os.makedirs(wear)
for tile, (w, h) in ((1001, (N, N)), (1002, (256, 1024))):
    path = os.path.join(wear, "wear.%d.exr" % tile)
    o = oiio.ImageOutput.create(path)
    o.open(path, oiio.ImageSpec(w, h, 1, oiio.FLOAT))
    if tile == 1001:  # three values: the energy audit's distinct latents are few
        px = (np.arange(w * h).reshape(h, w, 1) % 3 * 0.1 + 0.2).astype(np.float32)
    else:
        px = np.random.default_rng(tile).random((h, w, 1), dtype=np.float32) * 0.5 + 0.05
    o.write_image(px)
    o.close()
wear_image = bpy.data.images.load(os.path.join(wear, "wear.1001.exr"))
wear_image.source = "TILED"
big = bpy.data.materials.new("Cancel Set")
big.nbrdf_bake.alpha2_source, big.nbrdf_bake.alpha2_image = "IMAGE", wear_image
big.nbrdf_bake.output = os.path.join(work, "cancel", "{material}.exr")
big.nbrdf_bake.preview = False
session = Session.start(bpy.context, big)
# No deadline: the CLI ends either way, and ctest's timeout bounds a hang.
while session.poll() and session.bake.tile_index < 2:
    time.sleep(0.01)
session.cancel()
state = session.wait()
t.check("cancelled set: state %s (%s)" % (state, session.bake.message), state == "cancelled")
t.check("cancelled set: the report says what stays: %s" % session.report()[1],
        "tile 1002" in session.report()[1] and "1 finished tile kept" in session.report()[1])
left = sorted(os.listdir(os.path.join(work, "cancel")))
t.check("cancelled set: tile 1001 stays, nothing else: %s" % left,
        left == ["Cancel_Set.1001.exr"])

p = BakeProcess(["nbrdf"], os.path.join(latent, "Udim.<UDIM>.exr"))
for line in ('{"event":"progress","stage":"bake","done":32,"total":32,"tile":1001,'
             '"tile_index":1,"tiles":2}',
             '{"event":"tile","tile":1001,"index":1,"tiles":2,"status":"baked",'
             '"output":"Udim.1001.exr"}',
             '{"event":"progress","stage":"bake","done":8,"total":32,"tile":1002,'
             '"tile_index":2,"tiles":2}'):
    p._event(line)
t.check("set progress: %.3f" % p.progress, abs(p.progress - 0.625) < 1e-9)
t.check("tile progress: %.3f" % p.tile_progress, abs(p.tile_progress - 0.25) < 1e-9)
p._cancel_at = 0.0
p._finish(1)
t.check("cancelled set: %s" % p.message, p.state == "cancelled" and "tile 1002" in p.message
        and "1 finished tile kept" in p.message)

# 7. Write Farm Plan: the same bake arguments, a plan naming both tiles, not submitted; the
# tiles that exist only in Blender (the coat's) are kept in the plan's inputs/.
coat.image = coat_tiles
mat.node_tree.links.new(coat.outputs["Color"], bsdf.inputs["Clearcoat Roughness"])
s.output = "//latent/{material}.exr"
s.farm_plan = "//farm/{material}"
t.check("farm plan written", bpy.ops.nbrdf.write_farm_plan(material=mat.name) == {"FINISHED"})
plan = os.path.join(work, "farm", "Udim")
try:
    with open(os.path.join(plan, "plan.json")) as f:
        doc = json.load(f)
except (OSError, ValueError) as e:
    doc = {}
    t.check("plan.json: %s" % e, False)
t.check("plan names both tiles: %s" % doc.get("tiles"), doc.get("tiles") == [1001, 1002])
t.check("plan's jobs: a job per tile", {"tile-1001", "tile-1002"} <= {
    j.get("name") for j in doc.get("jobs", [])})
t.check("submit.sh written", os.path.isfile(os.path.join(plan, "submit.sh")))
t.check("not submitted", not os.path.exists(os.path.join(plan, "jobs.txt")))
t.check("the panel says what to run: %s" % s.farm_report,
        os.path.join(plan, "submit.sh") in s.farm_report and "1001, 1002" in s.farm_report)
kept = os.path.join(plan, "inputs")
names = sorted(os.listdir(kept)) if os.path.isdir(kept) else []
t.check("the coat's tiles kept for the farm: %s" % names,
        names == ["alpha1_coat.1001.exr", "alpha1_coat.1002.exr"])
command = " ".join(next((j["command"] for j in doc.get("jobs", []) if j.get("name") ==
                         "tile-1002"), []))
t.check("the tile job reads them: %s" % command,
        os.path.join(kept, "alpha1_coat.<UDIM>.exr") in command and "rough.<UDIM>.png" in command)
stamps = [os.stat(os.path.join(kept, n)).st_mtime_ns for n in names]
t.check("farm plan written again", bpy.ops.nbrdf.write_farm_plan(material=mat.name) == {"FINISHED"})
t.check("unchanged inputs left as they were (the farm skips baked tiles)",
        stamps == [os.stat(os.path.join(kept, n)).st_mtime_ns for n in names])
# The single-image material has no tile set to plan.
flat = bpy.data.materials.new("Flat")
try:
    bpy.ops.nbrdf.write_farm_plan(material=flat.name)
    message = None
except RuntimeError as e:
    message = str(e)
t.check("no tiled input: refused: %s" % message, message is not None and "tile set" in message)

# 8. Bake All Materials takes a tile set as one item: {object}_{material}.<UDIM>.exr.
bpy.ops.mesh.primitive_plane_add()
plane = bpy.context.active_object
plane.name = "Plane"
plane.data.materials.append(mat)
q = bpy.context.scene.nbrdf_queue
q.scope, q.output = "SELECTED", "//queue/{object}_{material}.exr"
bpy.ops.nbrdf.bake_all()
item = q.items[0] if len(q.items) == 1 else None
t.check("queue: the set baked: %s" % (item and item.message),
        item is not None and item.state == "DONE" and "Plane_Udim.<UDIM>.exr" in item.message)
t.check("queue: one texture per tile", sorted(os.listdir(os.path.join(work, "queue")))
        == ["Plane_Udim.1001.exr", "Plane_Udim.1002.exr"])

t.disable()
t.finish("test_udim")
