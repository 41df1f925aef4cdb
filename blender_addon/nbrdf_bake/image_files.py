"""Writes pixel arrays as 8-bit PNG or 32-bit float OpenEXR, without bpy.

Blender's own savers always write RGBA and, for 8-bit formats, may apply the scene's view
transform; the bake needs the image's values unchanged and grey maps kept to one channel
(an all-grey bake is mono, a third of the size). Both writers are minimal: no compression
in the EXR, no filtering in the PNG — these files live only for the duration of a bake.
"""

import struct
import zlib

import numpy as np


def write_png8(path, pixels):
    """pixels: uint8 array (height, width, 1 or 3), first row at the top."""
    h, w, c = pixels.shape
    if c not in (1, 3):
        raise ValueError("PNG: 1 or 3 channels, not %d" % c)
    rows = np.zeros((h, 1 + w * c), np.uint8)  # each row starts with filter type 0 (none)
    rows[:, 1:] = pixels.reshape(h, w * c)
    colour_type = 0 if c == 1 else 2
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        _png_chunk(f, b"IHDR", struct.pack(">IIBBBBB", w, h, 8, colour_type, 0, 0, 0))
        _png_chunk(f, b"IDAT", zlib.compress(rows.tobytes(), 6))
        _png_chunk(f, b"IEND", b"")


def _png_chunk(f, kind, data):
    f.write(struct.pack(">I", len(data)))
    f.write(kind)
    f.write(data)
    f.write(struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))


def write_exr_float(path, pixels):
    """pixels: float32 array (height, width, 1 or 3), first row at the top.

    One scanline part, uncompressed, FLOAT samples; channel Y for grey, else R, G, B.
    """
    h, w, c = pixels.shape
    if c not in (1, 3):
        raise ValueError("EXR: 1 or 3 channels, not %d" % c)
    names = ["Y"] if c == 1 else ["R", "G", "B"]
    order = sorted(range(c), key=lambda i: names[i])  # OpenEXR stores channels by name
    chlist = b"".join(names[i].encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1)
                      for i in order) + b"\0"
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    header = b"".join([
        _attr("channels", "chlist", chlist),
        _attr("compression", "compression", b"\0"),
        _attr("dataWindow", "box2i", box),
        _attr("displayWindow", "box2i", box),
        _attr("lineOrder", "lineOrder", b"\0"),
        _attr("pixelAspectRatio", "float", struct.pack("<f", 1.0)),
        _attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0)),
        _attr("screenWindowWidth", "float", struct.pack("<f", 1.0)),
    ]) + b"\0"
    data = np.ascontiguousarray(pixels, dtype="<f4")
    line_bytes = w * c * 4
    first = 8 + len(header) + 8 * h
    offsets = struct.pack("<%dQ" % h, *(first + y * (8 + line_bytes) for y in range(h)))
    with open(path, "wb") as f:
        f.write(struct.pack("<ii", 20000630, 2))  # magic, version 2, single-part scanline
        f.write(header)
        f.write(offsets)
        for y in range(h):
            f.write(struct.pack("<ii", y, line_bytes))
            for i in order:  # a line holds each channel's w samples in turn
                f.write(data[y, :, i].tobytes())


def _attr(name, kind, value):
    return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value
