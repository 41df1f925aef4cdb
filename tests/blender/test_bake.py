"""Bake Latent Texture on a material with generated (unsaved) images: the EXR has the
documented channels and equals, byte for byte, `nbrdf bake` run on the same pixels written
independently with OpenImageIO; the result comes back as a MULTILAYER image; temporary
inputs are removed; a failing bake (maps of two sizes) is reported and leaves no file;
a cancelled bake leaves no file."""

import filecmp
import os
import subprocess
import sys
import time

import bpy
import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import addon_testing as t  # noqa: E402

t.enable()
from nbrdf_bake.session import Session, has_render, preview_path  # noqa: E402

W, H = 24, 16
rng = np.random.default_rng(7)
work = t.temp_dir()


def generated(name, rgba, float_buffer=False, colour_space=None):
    """An unsaved image with the given (h, w, 4) pixels, first row at the top."""
    h, w = rgba.shape[:2]
    im = bpy.data.images.new(name, w, h, alpha=True, float_buffer=float_buffer)
    if colour_space:
        im.colorspace_settings.name = colour_space
    im.pixels.foreach_set(np.ascontiguousarray(rgba[::-1], np.float32).ravel())
    return im


def rgba(values):
    h, w, c = values.shape
    out = np.ones((h, w, 4), np.float32)
    out[..., :3] = values if c == 3 else np.repeat(values, 3, axis=2)
    return out


# 8-bit grey coat roughness, 8-bit sRGB base colour, float optical depth in [0, 5].
alpha1_bytes = rng.integers(20, 230, (H, W, 1), dtype=np.uint8)
r0_bytes = rng.integers(0, 256, (H, W, 3), dtype=np.uint8)
sigma_t = (rng.random((H, W, 1), dtype=np.float32) * 5.0).astype(np.float32)
im_alpha1 = generated("coat rough", rgba(alpha1_bytes / 255.0), colour_space="Non-Color")
im_r0 = generated("base.colour", rgba(r0_bytes / 255.0))
im_sigma = generated("depth", rgba(sigma_t), float_buffer=True)

mat = bpy.data.materials.new("Layered Test")
s = mat.nbrdf_bake
s.alpha1_source, s.alpha1_image = "IMAGE", im_alpha1
s.r0_source, s.r0_image = "IMAGE", im_r0
s.sigma_t_source, s.sigma_t_image = "IMAGE", im_sigma
s.eta_value, s.alpha2_value, s.albedo_value = 1.45, 0.3, (0.8, 0.7, 0.6)
s.output = os.path.join(work, "{material}.exr")
s.preview_size, s.preview_spp = 16, 1  # the preview, when nbrdf has render
out = os.path.join(work, "Layered_Test.exr")

# 1. The operator, run to completion (blocking execute: timers do not tick under -b).
before = t.bake_temp_dirs()
result = bpy.ops.nbrdf.bake_latent(material=mat.name)
t.check("operator finished: %s" % result, result == {"FINISHED"})
t.check("EXR written", os.path.isfile(out))
t.check("temporary inputs removed", t.bake_temp_dirs() == before)
t.check("no temporary output left", not t.temporaries(work))

inp = oiio.ImageInput.open(out)
t.check("OpenImageIO opens it", inp is not None)
spec = inp.spec()
want = {"latent.L%02d.%s" % (i, c) for i in range(32) for c in "RGB"}
want |= {"proxy.%s.%s" % (p, c) for p in ("sigma", "w") for c in "RGB"}
t.check("documented channels (%d)" % spec.nchannels, set(spec.channelnames) == want)
t.check("size %dx%d" % (spec.width, spec.height), (spec.width, spec.height) == (W, H))
t.check("half storage", spec.format == oiio.HALF)
t.check("tiled 64", spec.tile_width == 64)
levels = 0
while inp.seek_subimage(0, levels):
    levels += 1
t.check("full mip chain (%d levels)" % levels, levels == 5)  # 24x16 ... 1x1
inp.close()

img = s.result
t.check("result image loaded",
        img is not None and os.path.samefile(bpy.path.abspath(img.filepath), out))
if img is not None:
    t.check("result is MULTILAYER: %s" % img.type, img.type == "MULTILAYER")

if has_render(t.NBRDF):
    pv = s.preview_image
    t.check("preview rendered beside the texture", os.path.isfile(preview_path(out)))
    t.check("preview loaded", pv is not None and pv.size[0] == 16)
else:
    print("test_bake: this nbrdf has no 'render': preview not tested")
s.preview = False

# 2. The CLI on the same pixels, written by OpenImageIO under the names the add-on uses.
ref = t.temp_dir()


def write(name, pixels, fmt):
    o = oiio.ImageOutput.create(name)
    o.open(os.path.join(ref, name), oiio.ImageSpec(W, H, pixels.shape[2], fmt))
    o.write_image(pixels)
    o.close()


write("alpha1_coat_rough.png", alpha1_bytes, oiio.UINT8)
write("r0_base.colour.png", r0_bytes, oiio.UINT8)
write("sigma_t_depth.exr", sigma_t, oiio.FLOAT)
cli = subprocess.run(
    [t.NBRDF, "bake", "--bundle", t.BUNDLE, "--alpha1", "alpha1_coat_rough.png", "--eta", "1.45",
     "--alpha2", "0.3", "--r0", "r0_base.colour.png", "--albedo", "0.8,0.7,0.6",
     "--sigma-t", "sigma_t_depth.exr", "--roughness", "perceptual", "-o", "ref.exr"],
    cwd=ref, capture_output=True, text=True)
t.check("CLI bake: %s" % cli.stderr, cli.returncode == 0)
t.check("add-on EXR == CLI EXR, byte for byte",
        filecmp.cmp(out, os.path.join(ref, "ref.exr"), shallow=False))

# 3. A packed copy of an image bakes the same latents (its packed bytes are the input).
im_alpha1.pack()
s.output = os.path.join(work, "packed.exr")
t.check("packed: finished", bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})
a = oiio.ImageBuf(out).get_pixels(oiio.FLOAT)
b = oiio.ImageBuf(os.path.join(work, "packed.exr")).get_pixels(oiio.FLOAT)
t.check("packed: same latents", a is not None and b is not None and np.array_equal(a, b))

# 4. Maps of two sizes with Resample Maps off: the CLI's error (which names the option)
# reaches Blender's report; no file, no temporaries.
s.sigma_t_image = generated("small", rgba(np.full((8, 8, 1), 0.5, np.float32)), True)
s.output = os.path.join(work, "mismatch.exr")
s.resample = False
try:
    bpy.ops.nbrdf.bake_latent(material=mat.name)
    message = None
except RuntimeError as e:  # bpy.ops turns an ERROR report into RuntimeError
    message = str(e)
# The map is named as the user knows it (the image 'small'), not by the temporary file the
# add-on wrote it to (sigma_t_small.exr), which the user never saw.
t.check("mismatch reported as an error naming the image: %s" % message,
        message is not None and "nbrdf bake failed" in message and "image 'small'" in message
        and "sigma_t_small.exr" not in message)
t.check("mismatch: no file", not os.path.exists(os.path.join(work, "mismatch.exr")))
t.check("mismatch: no temporaries", not t.temporaries(work) and t.bake_temp_dirs() == before)
t.check("mismatch: the message says --resample bilinear", message and "--resample bilinear" in message)
# With it on (the default), the small map is resampled to the largest map's size.
s.resample = True
s.output = os.path.join(work, "resampled.exr")
t.check("resampled: finished", bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})
spec = oiio.ImageInput.open(s.output).spec()
t.check("resampled to the largest map: %dx%d" % (spec.width, spec.height),
        (spec.width, spec.height) == (W, H))
s.resample = False

# A usage error's whole text reaches the report: its cause, not only the hint to --help.
small = s.sigma_t_image
s.sigma_t_source = "VALUE"
s.eta_range = (2.0, 1.2)
try:
    bpy.ops.nbrdf.bake_latent(material=mat.name)
    message = None
except RuntimeError as e:
    message = str(e)
t.check("reversed IOR range: the cause reported: %s" % message,
        message is not None and "--eta-range expects LO,HI with LO < HI" in message)
s.eta_range = (1.0, 2.0)
s.sigma_t_source, s.sigma_t_image = "IMAGE", small

# Setup problems are reported before anything runs: a path relative to an unsaved .blend,
# an image parameter without an image.
s.output = "//latent/{material}.exr"
try:
    bpy.ops.nbrdf.bake_latent(material=mat.name)
    message = None
except RuntimeError as e:
    message = str(e)
t.check("relative output in an unsaved file: %s" % message, message and "save the" in message)
s.output = os.path.join(work, "mismatch.exr")
s.sigma_t_image = None
try:
    bpy.ops.nbrdf.bake_latent(material=mat.name)
    message = None
except RuntimeError as e:
    message = str(e)
t.check("missing image reported: %s" % message, message and "choose an image" in message)

# 5. Cancel: a bake of 4 bands of distinct float texels, cancelled after its first
# progress line (the session API the modal operator polls on its timer).
big = mat.copy()
big.name = "Cancel Me"
big.nbrdf_bake.result = None  # copied from the first material
noise = rng.random((1024, 256, 1), dtype=np.float32) * 0.5 + 0.05
big.nbrdf_bake.sigma_t_source = "VALUE"
big.nbrdf_bake.alpha1_source = "VALUE"
big.nbrdf_bake.r0_source = "VALUE"
big.nbrdf_bake.alpha2_source = "IMAGE"
big.nbrdf_bake.alpha2_image = generated("noise", rgba(noise), True)
big.nbrdf_bake.output = os.path.join(work, "cancelled.exr")
session = Session.start(bpy.context, big)
# No deadline: the CLI ends either way (a loaded machine is only slower), and ctest's
# timeout bounds a hang.
while session.poll() and session.bake.progress_events == 0:
    time.sleep(0.01)
session.cancel()
t.check("cancelling: the panel's state says so", session.cancelling or not session.poll())
state = session.wait()
t.check("cancelled: no longer cancelling", not session.cancelling)
t.check("cancelled: state %s (%s)" % (state, session.bake.message), state == "cancelled")
t.check("cancelled: report is a warning",
        session.report()[0] == "WARNING" and "no file" in session.report()[1])
t.check("cancelled: no file", not os.path.exists(os.path.join(work, "cancelled.exr")))
t.check("cancelled: no temporaries", not t.temporaries(work) and t.bake_temp_dirs() == before)
t.check("cancelled: no result image", big.nbrdf_bake.result is None)

t.disable()
t.finish("test_bake")
