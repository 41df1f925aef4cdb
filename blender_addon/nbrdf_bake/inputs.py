"""Turns a material's bake settings into `nbrdf bake` arguments.

Images with a file on disk are passed by absolute path. Packed images are written out as
their packed bytes; generated or edited (unsaved) images as an 8-bit PNG (8-bit buffers) or
a float EXR (float buffers), one channel when grey. Those go to a temporary folder that is
the CLI's working directory, under file names of their own (<param>_<image>.<ext>), so the
texture's nbrdf:parameterSources names them the same way whichever folder the bake ran in.
Tiled (UDIM) images become tile patterns the same way (tiled_images.py); with any of them
the bake is a tile set, its output a pattern too.
"""

import os
import re

import bpy
import numpy as np

from . import image_files, material_inputs, tiled_images, tiles, uv_bake
from .params import PARAMS, constant, number


class SetupError(Exception):
    pass


ROUGHNESS = {"PERCEPTUAL": "perceptual", "ALPHA": "alpha"}
LINEAR_SPACES = {"Non-Color", "Linear", "Raw"}
# OpenImageIO picks its reader by extension; packed images with no file name have none.
PACKED_EXT = {"PNG": ".png", "OPEN_EXR": ".exr", "OPEN_EXR_MULTILAYER": ".exr", "JPEG": ".jpg",
              "TIFF": ".tif", "TARGA": ".tga", "TARGA_RAW": ".tga", "HDR": ".hdr", "BMP": ".bmp"}


def output_path(settings, material_name, template=None, object_name=None):
    """The output file: `template` (default: the material's Output) with {material} and
    {object} replaced (an object's name only where one is given: the queue's)."""
    template = template or settings.output
    path = template.replace("{material}", file_name(material_name))
    if "{object}" in path:
        if object_name is None:
            raise SetupError("output '%s' has {object}, which only Bake All Materials fills in"
                             % template)
        path = path.replace("{object}", file_name(object_name))
    if path.startswith("//") and not bpy.data.filepath:
        raise SetupError("output '%s' is relative to the .blend file: save the file first or "
                         "choose an absolute output path" % template)
    path = bpy.path.abspath(path)
    if not path.lower().endswith(".exr"):
        raise SetupError("output '%s' must end in .exr" % path)
    return os.path.normpath(path)


def resolve_sources(context, material, settings, obj=None, uv_map=None):
    """{key: ("value", floats) | ("image", Image)} for the six parameters, the notes to
    report, and the images made here (UV bakes, removed by the caller after the bake).

    Sources: Value, Image, or From Material (the Principled BSDF, principled.py); an input
    that is neither a constant nor an Image Texture node is baked through `uv_map` (default:
    the active one) of `obj` (default: the active object) when Bake Through UV Map is on,
    else refused naming the material, the socket and the node."""
    specs, notes, made = {}, [], []
    reading = None
    for p in PARAMS:
        src = getattr(settings, p.key + "_source")
        if src == "MATERIAL":
            if p.key in ("alpha1", "alpha2") and settings.roughness != "PERCEPTUAL":
                raise SetupError("%s comes from the material, whose roughness is Blender's "
                                 "perceptual r: set Roughness to Perceptual (Blender)" % p.label)
            if reading is None:
                try:
                    reading, general = material_inputs.read(material)
                except material_inputs.MaterialError as e:
                    raise SetupError(str(e)) from e
                notes += general
            r = reading[p.key]
            notes += ["%s: %s" % (p.label, n) for n in r.notes]
            specs[p.key] = (r.kind, r.value if r.kind != "procedural" else r)
        else:
            specs[p.key] = _own_spec(settings, p)
    procedural = [(k, v[1]) for k, v in specs.items() if v[0] == "procedural"]
    if procedural and not settings.bake_uv:
        k, r = procedural[0]
        raise SetupError("%s: material '%s', input '%s' comes from %s: turn on Bake "
                         "Through UV Map, link an Image Texture, or set it by hand"
                         % (_label(k), material.name, r.socket, node_words(r.value)))
    tiled = [k for k, v in specs.items() if v[0] == "image" and tiled_images.is_tiled(v[1])]
    if procedural and tiled:
        k, r = procedural[0]
        raise SetupError("%s: material '%s', input '%s' comes from %s, and %s is a tiled "
                         "image: Bake Through UV Map makes one image, not a tile set; link "
                         "a tiled Image Texture or set it by hand"
                         % (_label(k), material.name, r.socket, node_words(r.value),
                            _label(tiled[0])))
    if procedural:
        w, h = output_size(settings, [v[1] for v in specs.values() if v[0] == "image"])
        if obj is None:
            obj = getattr(context, "object", None) or context.view_layer.objects.active
        try:
            for k, r in procedural:
                image = uv_bake.bake_socket(context, obj, material, r.value,
                                            "nbrdf %s %s" % (material.name, k), w, h,
                                            uv_map=uv_map)
                made.append(image)
                specs[k] = ("image", image)
        except uv_bake.UVBakeError as e:
            for im in made:
                bpy.data.images.remove(im)
            raise SetupError(str(e)) from e
    return specs, notes, made


def node_words(socket):
    """"node 'Noise.001' (Noise Texture)": the user's node feeding `socket`, by the name the
    Node Editor shows and its kind."""
    node = socket.links[0].from_node
    kind = node.bl_label or node.type
    return ("node '%s'" % node.name) + ("" if kind == node.name else " (%s)" % kind)


def _label(key):
    return next(p.label for p in PARAMS if p.key == key)


def any_tiled(specs):
    """Whether an input is a tiled image: the bake is then a tile set."""
    return any(kind == "image" and tiled_images.is_tiled(v) for kind, v in specs.values())


def set_output(output, specs):
    """The output of a tile set is a pattern (`<UDIM>` added before .exr); else as given."""
    return tiles.with_udim(output) if any_tiled(specs) else output


def output_size(settings, images):
    """The texture's size: the chosen size, or (Auto) the largest image among the inputs,
    and the chosen size when every input is a constant or procedural."""
    if settings.size_mode == "CUSTOM" or not images:
        return tuple(settings.size)
    return (max(im.size[0] for im in images), max(im.size[1] for im in images))


def param_argv(settings, specs, workdir):
    """The inputs' arguments, shared by `nbrdf bake` and `nbrdf verify`, and the map sizes."""
    argv, sizes = [], []
    for p in PARAMS:
        kind, value = specs[p.key]
        if kind == "image":
            argv += [p.flag, image_file(value, p.key, workdir)]
            sizes.append(tuple(value.size))
            if p.colour:
                space = _colour_space(settings.colour_maps, value, p.label)
                argv += ["--%s-colourspace" % p.key, space]
        else:
            argv += [p.flag, constant(value)]
    argv += ["--eta-range", ",".join(number(v) for v in settings.eta_range),
             "--sigma-t-range", ",".join(number(v) for v in settings.sigma_t_range),
             "--roughness", ROUGHNESS[settings.roughness]]
    return argv, sizes


def size_argv(settings, sizes, images):
    """--size (and --resample bilinear where a map's size differs, when allowed)."""
    w, h = output_size(settings, images)
    argv = []
    if not sizes or settings.size_mode == "CUSTOM" or any(sz != (w, h) for sz in sizes):
        argv += ["--size", "%dx%d" % (w, h)]
    if settings.resample and any(sz != (w, h) for sz in sizes):
        argv += ["--resample", "bilinear"]
    return argv


def build_argv(nbrdf, bundle, settings, material_name, workdir, specs=None, output=None):
    """Returns (argv, output, inputs argv); writes the images that have no usable file into
    workdir. `specs` from resolve_sources (default: the panel's values and images); `output`
    default: output_path(settings, material_name)."""
    output = output or output_path(settings, material_name)
    if specs is None:
        specs = {p.key: _own_spec(settings, p) for p in PARAMS}
    params, sizes = param_argv(settings, specs, workdir)
    images = [v for k, v in specs.values() if k == "image"]
    if any(tiled_images.is_tiled(im) for im in images):
        size = tiled_images.size_argv(settings, images)
    else:
        size = size_argv(settings, sizes, images)
    # verify sizes the maps to the texture itself; it needs only the resampling flag
    params += [a for a in size if a in ("--resample", "bilinear")]
    argv = [nbrdf, "bake", "--progress=json", "--bundle", bundle] + params
    argv += [a for a in size if a not in ("--resample", "bilinear")]
    argv += ["--range", settings.range_policy.lower(),
             "--half" if settings.storage == "HALF" else "--float",
             "--mip-levels", "full" if settings.mip_levels == "FULL" else "1",
             "--tile", str(settings.tile)]
    argv += accuracy_argv(settings)
    argv += ["-o", output]
    return argv, output, params


def accuracy_argv(settings):
    """--accuracy, --max-error, --compact and --budget; nothing for the fast level, so its bytes stay the
    CLI's."""
    if settings.accuracy == "FAST":
        return []
    argv = ["--accuracy", settings.accuracy.lower()]
    if settings.accuracy == "AUTO":
        argv += ["--max-error", number(settings.max_error)]
    if settings.accuracy == "COMPACT":
        argv += ["--compact", str(settings.compact_channels)]
    if settings.budget > 0:
        argv += ["--budget", number(settings.budget)]
    return argv


def _own_spec(settings, p):
    if getattr(settings, p.key + "_source") == "IMAGE":
        image = getattr(settings, p.key + "_image")
        if image is None:
            raise SetupError("%s: choose an image or switch it to a value" % p.label)
        return ("image", image)
    return ("value", _values(getattr(settings, p.key + "_value")))


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


def file_name(name):
    return re.sub(r"[^A-Za-z0-9._-]+", "_", name).strip("._") or "image"


def image_file(image, key, workdir):
    """A path the CLI can read with the image's pixels: its own file when it has one; a tile
    pattern for a tiled image."""
    if image.source == "TILED":
        return tiled_images.tiled_file(image, key, workdir)
    if image.source not in {"FILE", "GENERATED"}:
        raise SetupError("image '%s': %s images cannot be baked (a single image or a tiled "
                         "one is needed)" % (image.name, image.source.lower()))
    base = os.path.join(workdir, key + "_" + file_name(image.name))
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
    return write_pixels(image, base)


def write_pixels(image, base):
    """Writes the image's pixels to base + .png (8-bit buffers) or .exr (float); returns the
    file's name."""
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
