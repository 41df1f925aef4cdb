"""Turns a material's bake settings into `nbrdf bake` arguments.

Images with a file on disk are passed by absolute path. Packed images are written out as
their packed bytes; generated or edited (unsaved) images as an 8-bit PNG (8-bit buffers) or
a float EXR (float buffers), one channel when grey. Those go to a temporary folder that is
the CLI's working directory, under file names of their own (<param>_<image>.<ext>), so the
texture's nbrdf:parameterSources names them the same way whichever folder the bake ran in.
"""

import os
import re

import bpy
import numpy as np

from . import image_files
from .params import PARAMS, constant, number


class SetupError(Exception):
    pass


ROUGHNESS = {"PERCEPTUAL": "perceptual", "ALPHA": "alpha"}
LINEAR_SPACES = {"Non-Color", "Linear", "Raw"}
# OpenImageIO picks its reader by extension; packed images with no file name have none.
PACKED_EXT = {"PNG": ".png", "OPEN_EXR": ".exr", "OPEN_EXR_MULTILAYER": ".exr", "JPEG": ".jpg",
              "TIFF": ".tif", "TARGA": ".tga", "TARGA_RAW": ".tga", "HDR": ".hdr", "BMP": ".bmp"}


def output_path(settings, material_name):
    path = settings.output.replace("{material}", _file_name(material_name))
    if path.startswith("//") and not bpy.data.filepath:
        raise SetupError("output '%s' is relative to the .blend file: save the file first or "
                         "choose an absolute output path" % settings.output)
    path = bpy.path.abspath(path)
    if not path.lower().endswith(".exr"):
        raise SetupError("output '%s' must end in .exr" % path)
    return os.path.normpath(path)


def build_argv(nbrdf, bundle, settings, material_name, workdir):
    """Returns (argv, output); writes the images that have no usable file into workdir."""
    output = output_path(settings, material_name)
    argv = [nbrdf, "bake", "--progress=json", "--bundle", bundle]
    for p in PARAMS:
        image = getattr(settings, p.key + "_image")
        if getattr(settings, p.key + "_source") == "IMAGE":
            if image is None:
                raise SetupError("%s: choose an image or switch it to a value" % p.label)
            argv += [p.flag, image_file(image, p.key, workdir)]
            if p.colour:
                space = _colour_space(settings.colour_maps, image, p.label)
                argv += ["--%s-colourspace" % p.key, space]
        else:
            argv += [p.flag, constant(_values(getattr(settings, p.key + "_value")))]
    argv += ["--eta-range", ",".join(number(v) for v in settings.eta_range),
             "--sigma-t-range", ",".join(number(v) for v in settings.sigma_t_range),
             "--roughness", ROUGHNESS[settings.roughness],
             "--range", settings.range_policy.lower(),
             "--half" if settings.storage == "HALF" else "--float",
             "--mip-levels", "full" if settings.mip_levels == "FULL" else "1",
             "--tile", str(settings.tile), "-o", output]
    return argv, output


def _values(v):
    return list(v) if hasattr(v, "__len__") else [v]


def _colour_space(choice, image, label):
    if choice == "SRGB":
        return "srgb"
    if choice == "LINEAR":
        return "linear"
    name = image.colorspace_settings.name
    if name == "sRGB":
        return "srgb"
    if name in LINEAR_SPACES:
        return "linear"
    raise SetupError("%s: image '%s' is in colour space '%s'; the bake knows sRGB and linear: "
                     "set the image's colour space or the panel's Colour Maps"
                     % (label, image.name, name))


def _file_name(name):
    return re.sub(r"[^A-Za-z0-9._-]+", "_", name).strip("._") or "image"


def image_file(image, key, workdir):
    """A path the CLI can read with the image's pixels: its own file when it has one."""
    if image.source == "TILED" or image.source not in {"FILE", "GENERATED"}:
        raise SetupError("image '%s': %s images cannot be baked (a single image is needed)"
                         % (image.name, image.source.lower()))
    base = os.path.join(workdir, key + "_" + _file_name(image.name))
    if image.source == "FILE" and not image.is_dirty:
        if image.packed_file:
            ext = os.path.splitext(image.filepath)[1] or PACKED_EXT.get(image.file_format, "")
            with open(base + ext, "wb") as f:
                f.write(image.packed_file.data)
            return os.path.basename(base + ext)
        path = os.path.normpath(bpy.path.abspath(image.filepath, library=image.library))
        if not os.path.isfile(path):
            raise SetupError("image '%s': file '%s' not found" % (image.name, path))
        return path
    return _write_pixels(image, base)


def _write_pixels(image, base):
    w, h = image.size
    c = image.channels
    if w == 0 or h == 0:
        raise SetupError("image '%s' has no pixels" % image.name)
    buf = np.empty(w * h * c, np.float32)
    image.pixels.foreach_get(buf)
    # Blender's rows start at the bottom; image files' at the top.
    px = buf.reshape(h, w, c)[::-1, :, :min(c, 3)]
    if px.shape[2] == 3 and (px[..., 0] == px[..., 1]).all() and (px[..., 0] == px[..., 2]).all():
        px = px[..., :1]
    if px.shape[2] == 2:  # grey + alpha
        px = px[..., :1]
    if image.is_float:
        path = base + ".exr"
        image_files.write_exr_float(path, np.ascontiguousarray(px))
    else:
        path = base + ".png"  # 8-bit buffers read back as byte / 255: exact on the way out
        image_files.write_png8(path, np.rint(px * 255.0).clip(0, 255).astype(np.uint8))
    return os.path.basename(path)
