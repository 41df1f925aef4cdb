"""Tiled (UDIM) images as `nbrdf bake` tile patterns, and a baked tile set loaded back.

An image whose tiles all lie on disk (and are unchanged) is passed as its own pattern, so
the CLI reads the artist's files; packed tiles are written out as their packed bytes; tiles
that exist only in Blender (generated, painted, added and never saved) are saved by Blender
into the temporary folder and rewritten there as the single-image path writes pixels
(inputs.write_pixels: exact values, grey kept to one channel). Every temporary tile is
named <param>_<image>.<tile>.<ext> and passed as <param>_<image>.<UDIM>.<ext>.

A tile set's bake skips a tile whose texture records the same inputs: each map's path, size
and modification time (docs/FARM.md, "Resume"). A temporary tile is written anew by every
bake, so its time is set from its bytes (stamp()): unchanged pixels give the same time and the
tile is skipped on a re-run; a painted tile gets another and is baked again.
"""

import hashlib
import os

import bpy
import numpy as np

from . import inputs, tiles


def is_tiled(image):
    return image is not None and image.source == "TILED"


def numbers(image):
    return sorted(t.number for t in image.tiles)


def tiled_file(image, key, workdir):
    """The pattern the CLI reads for `image` (absolute: its own files; else a name in
    workdir)."""
    base = os.path.join(workdir, key + "_" + inputs.file_name(image.name))
    if image.packed_files and not image.is_dirty:
        return _write_packed(image, base)
    if image.filepath and not image.is_dirty:
        path = os.path.normpath(bpy.path.abspath(image.filepath, library=image.library))
        pattern = tiles.pattern_of(path)
        if pattern is None:
            raise inputs.SetupError("tiled image '%s': its file '%s' names no tile (neither "
                                    "<UDIM> nor a tile number)" % (image.name, path))
        if all(os.path.isfile(tiles.tile_path(pattern, n)) for n in numbers(image)):
            return pattern
        # Some tiles were added in Blender and never saved: write the set as Blender has it.
    return _write_tiles(image, base)


def _write_packed(image, base):
    exts = set()
    for pf in image.packed_files:
        ext = (os.path.splitext(pf.filepath)[1]
               or inputs.PACKED_EXT.get(image.file_format, ""))
        exts.add(ext)
        path = "%s.%d%s" % (base, pf.tile_number, ext)
        with open(path, "wb") as f:
            f.write(pf.packed_file.data)
        stamp(path)
    if len(exts) != 1:
        raise inputs.SetupError("tiled image '%s': its packed tiles are of different file "
                                "types (%s); one pattern needs one" % (image.name,
                                                                       ", ".join(sorted(exts))))
    return os.path.basename(base) + ".<UDIM>" + exts.pop()


def _write_tiles(image, base):
    """Blender's saver writes every tile (Python reads only the first tile's pixels); each is
    read back and written again with the values unchanged and grey as one channel. The saver
    keeps the image's path but marks its tiles saved: an image with unsaved paint is marked
    unsaved again (its first tile's pixels rewritten as they are), so Blender still offers to
    save it and then writes every tile. (Like Blender's own save, an 8-bit tile with no alpha
    channel is written with any painted alpha below 1 multiplied in.)"""
    folder = base + ".saved"
    os.makedirs(folder, exist_ok=True)
    ext = ".exr" if image.is_float else ".png"
    saved_format = image.file_format
    unsaved = image.is_dirty
    image.file_format = "OPEN_EXR" if image.is_float else "PNG"
    try:
        image.save(filepath=os.path.join(folder, "tile.<UDIM>" + ext))
    except RuntimeError as e:
        raise inputs.SetupError("tiled image '%s': its tiles could not be written for the "
                                "bake: %s" % (image.name, str(e).strip())) from e
    finally:
        image.file_format = saved_format
        if unsaved and not image.is_dirty:
            first = np.empty(len(image.pixels), np.float32)
            image.pixels.foreach_get(first)
            image.pixels.foreach_set(first)
    written = set()
    for n in numbers(image):
        path = os.path.join(folder, "tile.%d%s" % (n, ext))
        if not os.path.isfile(path):
            raise inputs.SetupError("tiled image '%s': tile %d has no pixels (fill it or "
                                    "remove it)" % (image.name, n))
        tile = bpy.data.images.load(path, check_existing=False)
        try:
            name = inputs.write_pixels(tile, "%s.%d" % (base, n))
        finally:
            bpy.data.images.remove(tile)
        stamp(os.path.join(os.path.dirname(base), name))
        written.add(os.path.splitext(name)[1])
    return os.path.basename(base) + ".<UDIM>" + written.pop()


# 2001-09-09: a time no tool takes for "now", far from 0 (which some treat as unset).
_STAMP_BASE_NS = 1_000_000_000 * 10**9


def stamp(path):
    """Sets the file's modification time from its bytes (within ~18 minutes after
    _STAMP_BASE_NS, in nanoseconds): equal bytes, equal time."""
    with open(path, "rb") as f:
        digest = hashlib.sha256(f.read()).digest()
    ns = _STAMP_BASE_NS + int.from_bytes(digest[:5], "little")
    os.utime(path, ns=(ns, ns))


def size_argv(settings, images):
    """--size and --resample for a set: the Custom size applies to every tile; at Largest
    Map each tile takes its own maps' size (no --size), and --resample bilinear is passed
    when, with Resample Maps on, some tile's maps differ in size (among themselves or from the
    Custom size)."""
    custom = tuple(settings.size) if settings.size_mode == "CUSTOM" else None
    per_tile = {}
    for im in images:
        if is_tiled(im):
            for t in im.tiles:
                per_tile.setdefault(t.number, set()).add(tuple(t.size))
    single = {tuple(im.size) for im in images if not is_tiled(im)}
    differ = any(len(sizes | single | ({custom} if custom else set())) > 1
                 for sizes in per_tile.values())
    argv = ["--size", "%dx%d" % custom] if custom else []
    if settings.resample and differ:
        argv += ["--resample", "bilinear"]
    return argv


def load_result(pattern, relative=False):
    """The baked set as one tiled image (source TILED, its tiles those on disk), reloaded
    when one already shows that pattern. `relative`: stored relative to the .blend."""
    image = None
    for im in bpy.data.images:
        if im.source == "TILED" and im.filepath and os.path.normpath(
                bpy.path.abspath(im.filepath)) == pattern:
            image = im
            break
    if image is None:
        first = _first_tile(pattern)
        image = bpy.data.images.load(first, check_existing=False)
        image.source = "TILED"  # Blender puts <UDIM> in its path and finds the other tiles
        image.filepath = pattern
    image.reload()  # tiles baked since are found too
    # Reading a tile's size opens the files: the image becomes MULTILAYER now (layers latent
    # and proxy), as the single result does.
    for t in image.tiles:
        t.size[0]
    if relative and bpy.data.filepath:
        try:
            image.filepath = bpy.path.relpath(pattern)
        except ValueError:  # another drive: stays absolute
            pass
    return image


def _first_tile(pattern):
    for n in range(tiles.FIRST, tiles.LAST + 1):
        path = tiles.tile_path(pattern, n)
        if os.path.isfile(path):
            return path
    raise inputs.SetupError("no tile of '%s' was written" % pattern)
