#!/usr/bin/env python3
"""Writes a few small safetensors files (laid out as the reference implementation writes
them) into the directory given, as seeds for fuzz_safetensors. Standard library only."""
import json
import os
import struct
import sys


def safetensors(tensors, metadata=None, pretty=False):
    """tensors: list of (name, dtype, shape, raw bytes), in file order."""
    header, offset = {}, 0
    if metadata is not None:
        header["__metadata__"] = metadata
    for name, dtype, shape, raw in tensors:
        header[name] = {"dtype": dtype, "shape": shape,
                        "data_offsets": [offset, offset + len(raw)]}
        offset += len(raw)
    text = json.dumps(header, indent=1 if pretty else None,
                      separators=None if pretty else (",", ":")).encode()
    text += b" " * (-len(text) % 8)
    return struct.pack("<Q", len(text)) + text + b"".join(t[3] for t in tensors)


def f32(*v):
    return struct.pack("<%df" % len(v), *v)


def main(out):
    os.makedirs(out, exist_ok=True)
    seeds = {
        "f32_meta": safetensors([("fc.bias", "F32", [3], f32(0.5, -1, 2)),
                                 ("fc.weight", "F32", [3, 2], f32(*range(6)))],
                                {"arch": "decoder", "width": "3"}),
        "mixed_dtypes": safetensors([("d", "F64", [2], struct.pack("<2d", 1.0, -0.1)),
                                     ("b", "BF16", [3], struct.pack("<3H", 0x3f80, 0xc020, 0x4049)),
                                     ("h", "F16", [2, 3], struct.pack("<6H", 0x3c00, 0xc000, 0x3800,
                                                                      0x7bff, 0x0001, 0xfc00))],
                                    {"format": "pt"}, pretty=True),
        "empty": safetensors([]),
        "scalar_and_empty": safetensors([("s", "F32", [], f32(42)),
                                         ("z", "F32", [0, 4], b"")], None),
        "escapes": safetensors([("caf\u00e9 \"q\"\n\U0001F600", "F32", [1], f32(1))],
                               {"note": "tab\there"}),
        "unsupported_i64": safetensors([("n", "I64", [1], struct.pack("<q", 7))]),
    }
    for name, data in seeds.items():
        with open(os.path.join(out, name + ".safetensors"), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "fuzz-out/seeds")
