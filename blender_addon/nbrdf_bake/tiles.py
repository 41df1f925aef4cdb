"""UDIM tile patterns as the CLI reads them (docs/FARM.md, "Tile patterns"), without bpy.

A pattern is a path with one tile token in its file name: `rough.<UDIM>.png` names
`rough.1001.png`, `rough.1002.png`, ... The add-on writes `<UDIM>` itself; the other tokens
are understood where a user typed them (an Output path with `<UVTILE>`, say).
"""

import os
import re

# Blender's own tokens first: <UDIM> and <UVTILE> are what a tiled image's path holds.
TOKEN = re.compile(r"<UDIM>|%\(UDIM\)d|<UVTILE>|<uvtile>|<[uUvV]>")
FIRST, LAST = 1001, 1100  # the tiles the CLI takes: u and v 0..9
# A tile number in a file name that Blender shows with the number instead of the token
# (an image opened from `rough.1001.png` in an older Blender): the last such number.
_NUMBER = re.compile(r"(?<![0-9])(1[0-9]{3})(?![0-9])")


def is_pattern(path):
    return bool(TOKEN.search(os.path.basename(path)))


def uv(tile):
    """(u, v) of a tile number, both from 0."""
    return (tile - 1001) % 10, (tile - 1001) // 10


def tile_path(pattern, tile):
    """The file of `tile` named by `pattern` (a plain path names the same file for every
    tile)."""
    u, v = uv(tile)
    words = {"<UDIM>": str(tile), "%(UDIM)d": str(tile), "<UVTILE>": "u%d_v%d" % (u + 1, v + 1),
             "<uvtile>": "u%d_v%d" % (u + 1, v + 1), "<u>": str(u), "<v>": str(v),
             "<U>": str(u + 1), "<V>": str(v + 1)}
    folder, name = os.path.split(pattern)
    return os.path.join(folder, TOKEN.sub(lambda m: words[m.group(0)], name))


def pattern_of(path):
    """A tiled image's file path as a pattern: as it is when it holds a token, else its file
    name's last tile number (1001..1999) made `<UDIM>`; None when it has neither."""
    if is_pattern(path):
        return path
    folder, name = os.path.split(path)
    found = list(_NUMBER.finditer(name))
    if not found:
        return None
    m = found[-1]
    return os.path.join(folder, name[:m.start()] + "<UDIM>" + name[m.end():])


def with_udim(path):
    """`path` as a pattern: unchanged when it is one, else `<UDIM>` before its extension
    (`//latent/rock.exr` -> `//latent/rock.<UDIM>.exr`)."""
    if is_pattern(path):
        return path
    stem, ext = os.path.splitext(path)
    return stem + ".<UDIM>" + ext


def name_regex(name):
    """A compiled regex matching the file names a pattern's file name `name` expands to."""
    parts, end = [], 0
    for m in TOKEN.finditer(name):
        parts.append(re.escape(name[end:m.start()]))
        parts.append(r"u[0-9]+_v[0-9]+" if m.group(0).lower() == "<uvtile>" else r"[0-9]+")
        end = m.end()
    parts.append(re.escape(name[end:]))
    return re.compile("".join(parts) + r"\Z")
