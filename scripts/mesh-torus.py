#!/usr/bin/env python3
"""Writes a UV-mapped torus (ring radius R, tube radius r, y up) as OBJ, ASCII PLY or binary
PLY: the test and benchmark mesh of `nbrdf render --mesh` (docs/RENDER.md, "Meshes").
usage: mesh-torus.py OUT.{obj,ply} [--rings 64] [--sides 80] [--binary]
Triangles: 2 x rings x sides (64 x 80 gives 10,240)."""
import argparse
import math
import struct

ap = argparse.ArgumentParser()
ap.add_argument("out")
ap.add_argument("--rings", type=int, default=64)
ap.add_argument("--sides", type=int, default=80)
ap.add_argument("--R", type=float, default=1.0)
ap.add_argument("--r", type=float, default=0.4)
ap.add_argument("--binary", action="store_true")
a = ap.parse_args()

verts = []  # (x, y, z, u, v, nx, ny, nz); the seam vertices are duplicated for the UVs
for i in range(a.rings + 1):
    phi = 2 * math.pi * i / a.rings
    for j in range(a.sides + 1):
        th = 2 * math.pi * j / a.sides
        n = (math.cos(th) * math.cos(phi), math.sin(th), math.cos(th) * math.sin(phi))
        c = (a.R * math.cos(phi), 0.0, a.R * math.sin(phi))
        p = tuple(c[k] + a.r * n[k] for k in range(3))
        verts.append(p + (i / a.rings, j / a.sides) + n)
faces = []
w = a.sides + 1
for i in range(a.rings):
    for j in range(a.sides):
        v00, v01, v10, v11 = i * w + j, i * w + j + 1, (i + 1) * w + j, (i + 1) * w + j + 1
        faces.append((v00, v01, v11))  # outward (counter-clockwise seen from outside)
        faces.append((v00, v11, v10))

if a.out.endswith(".obj"):
    with open(a.out, "w") as f:
        f.write("# torus: %d triangles\n" % len(faces))
        for v in verts:
            f.write("v %.7g %.7g %.7g\nvt %.7g %.7g\nvn %.7g %.7g %.7g\n" % v)
        for t in faces:
            f.write("f %s\n" % " ".join("%d/%d/%d" % (k + 1, k + 1, k + 1) for k in t))
else:
    head = ("ply\nformat %s 1.0\ncomment torus\nelement vertex %d\n"
            "property float x\nproperty float y\nproperty float z\n"
            "property float s\nproperty float t\n"
            "property float nx\nproperty float ny\nproperty float nz\n"
            "element face %d\nproperty list uchar uint vertex_indices\nend_header\n"
            % ("binary_little_endian" if a.binary else "ascii", len(verts), len(faces)))
    with open(a.out, "wb") as f:
        f.write(head.encode())
        for v in verts:
            f.write(struct.pack("<8f", *v) if a.binary else
                    ("%.7g %.7g %.7g %.7g %.7g %.7g %.7g %.7g\n" % v).encode())
        for t in faces:
            f.write(struct.pack("<B3I", 3, *t) if a.binary else ("3 %d %d %d\n" % t).encode())
