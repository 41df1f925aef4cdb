#!/usr/bin/env bash
# Regenerates the bad-map corpus in this folder (committed; run by hand):
# maps `nbrdf bake` must refuse with a message naming the file, and two RGBA
# maps whose colour under alpha = 0 must be read as stored. Needs oiiotool.
set -euo pipefail
cd "$(dirname "$0")"
t=$(mktemp -d)
trap 'rm -rf "$t"' EXIT
oiiotool --pattern fill:top=0.1,0.2,0.3:bottom=0.9,0.8,0.7 8x8 3 -d uint8 -o "$t/rgb.png"
oiiotool --pattern constant:color=1 2x2 1 -d float --compression none -o "$t/one.exr"
oiiotool --pattern fill:top=0.5:bottom=0.25 4x4 1 -d half -o "$t/grey.exr"
head -c 120 "$t/rgb.png" >truncated.png
head -c 200 "$t/grey.exr" >truncated.exr
: >empty.png
echo "not an image" >text.png
python3 - "$t" <<'PY'
import struct, sys, zlib
t = sys.argv[1]
png = bytearray(open(t + "/rgb.png", "rb").read())
i = png.index(b"IDAT") + 10
png[i] ^= 0x40                                   # a flipped bit inside the image data
open("bitflip.png", "wb").write(png)
one = open(t + "/one.exr", "rb").read()
def last_texel(value):                           # the header holds 1.0 too
    i = one.rindex(struct.pack("<f", 1.0))
    return one[:i] + value + one[i + 4:]
open("nan.exr", "wb").write(last_texel(struct.pack("<I", 0x7FC00000)))
open("inf.exr", "wb").write(last_texel(struct.pack("<I", 0x7F800000)))
open("negative.exr", "wb").write(last_texel(struct.pack("<f", -0.5)))
def png_file(w, h, ctype, rows):
    def chunk(k, d):
        return struct.pack(">I", len(d)) + k + d + struct.pack(">I", zlib.crc32(k + d))
    raw = b"".join(b"\0" + bytes(r) for r in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, ctype, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
# RGBA 2x1: (230, 128, 51) under alpha 0, then (230, 128, 51) under alpha 255.
open("rgba_alpha0.png", "wb").write(png_file(2, 1, 6, [[230, 128, 51, 0, 230, 128, 51, 255]]))
# Grey + alpha 2x1: 200 under alpha 0, 200 under alpha 128.
open("grey_alpha0.png", "wb").write(png_file(2, 1, 4, [[200, 0, 200, 128]]))
# A chunk that claims 3.6 GB (libpng would allocate it before finding the end).
good = png_file(1, 1, 0, [[7]])
end = good.index(b"IEND") - 4
open("chunk_length.png", "wb").write(good[:end] + struct.pack(">I", 0xDA2AB64D) + b"tEXt" + b"x" * 16)
# An OpenEXR header attribute that claims 1.7 GB.
exr = bytearray(open(t + "/grey.exr", "rb").read())
i = exr.index(b"channels\0chlist\0") + len("channels\0chlist\0")
exr[i:i + 4] = struct.pack("<I", 0x69726F00)
open("attr_length.exr", "wb").write(exr)
# A box2i attribute that declares 7 bytes: OpenEXR's C++ reader reads 16 anyway and takes
# the next attribute's size from the wrong bytes (fuzz_param_map: a 1.9 GB allocation).
exr = bytearray(open(t + "/grey.exr", "rb").read())
i = exr.index(b"dataWindow\0box2i\0") + len("dataWindow\0box2i\0")
exr[i:i + 4] = struct.pack("<I", 7)
open("box2i_size.exr", "wb").write(exr)
PY
oiiotool --pattern constant:color=0.2,0.4 2x2 2 --chnames U,V -d half -o two_channels.exr
oiiotool --pattern constant:color=0.1,0.2,0.3,0.4,0.5 2x2 5 -d half -o five_channels.exr
# A PGM header claiming 60000x60000 texels over 3 bytes of data.
printf 'P5 60000 60000 255\n\001\002\003' >dense.pgm
ls -l
# huge.bmp (54 bytes, claims 1048579x3 texels: OpenImageIO's reader allocated 805 MB),
# huge.pgm (18 bytes claiming 2222224x3 texels: 569 MB), rle8_24bit.bmp (24-bit texels with 8-bit run-length compression: OpenImageIO crashed) and
# damaged_chunk.exr are not made here: fuzz_param_map found it (a ZIP chunk OpenEXR's C++
# reader decodes partly, leaving texels of uninitialised memory); kept as found.
