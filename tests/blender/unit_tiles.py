"""Unit test of the add-on's tile patterns (tiles.py), plain Python: expansion as
docs/FARM.md's table gives it (tile 1003 is u 2, v 0), a tiled image's path that shows a
tile number made a pattern, <UDIM> added to an output, and the file names a pattern matches
(the CLI's temporary files beside a set). Run by test_tiles.sh."""

import os
import sys

sys.path.insert(0, os.path.join(os.environ["NBRDF_SOURCE_DIR"], "blender_addon", "nbrdf_bake"))
import tiles  # noqa: E402  (the module alone: no bpy, no package import)

failures = []


def check(what, got, want):
    if got != want:
        failures.append(what)
        print("FAIL: %s: %r, expected %r" % (what, got, want), file=sys.stderr)


for pattern, want in (("rough.<UDIM>.exr", "rough.1003.exr"),
                      ("rough.%(UDIM)d.exr", "rough.1003.exr"),
                      ("rough_u<u>_v<v>.exr", "rough_u2_v0.exr"),
                      ("rough_u<U>_v<V>.exr", "rough_u3_v1.exr"),
                      ("rough.<UVTILE>.exr", "rough.u3_v1.exr"),
                      ("rough.exr", "rough.exr")):
    check("tile 1003 of %s" % pattern, tiles.tile_path(pattern, 1003), want)
check("tile 1011 of <UDIM>", tiles.tile_path("/a/b.<UDIM>.png", 1011), "/a/b.1011.png")
check("tile 1011 of <UVTILE>", tiles.tile_path("b.<UVTILE>.png", 1011), "b.u1_v2.png")
check("a token in a folder is not a pattern", tiles.is_pattern("/x<UDIM>/a.png"), False)

check("a path with the token", tiles.pattern_of("/t/rough.<UDIM>.png"), "/t/rough.<UDIM>.png")
check("a path with a tile number", tiles.pattern_of("/t/rough.1001.png"), "/t/rough.<UDIM>.png")
check("the last tile number", tiles.pattern_of("/t/v1001_rough.1002.png"),
      "/t/v1001_rough.<UDIM>.png")
check("a longer number is none", tiles.pattern_of("/t/rough.10011.png"), None)
check("no number", tiles.pattern_of("/t/rough.png"), None)

check("output made a set", tiles.with_udim("//latent/Rock.exr"), "//latent/Rock.<UDIM>.exr")
check("output already a set", tiles.with_udim("//latent/Rock.<UVTILE>.exr"),
      "//latent/Rock.<UVTILE>.exr")

names = tiles.name_regex("Rock.<UDIM>.exr")
check("names: a tile", bool(names.match("Rock.1002.exr")), True)
check("names: another set", bool(names.match("Rocky.1002.exr")), False)
check("names: a longer name", bool(names.match("Rock.1002.exr.bak")), False)
check("names: <UVTILE>", bool(tiles.name_regex("R.<UVTILE>.exr").match("R.u1_v2.exr")), True)

if failures:
    print("unit_tiles: %d failed" % len(failures))
    sys.exit(1)
print("unit_tiles: ok")
