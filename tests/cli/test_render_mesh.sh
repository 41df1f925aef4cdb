#!/usr/bin/env bash
# 'nbrdf render --mesh' (issue 33): a torus as OBJ, ASCII and binary PLY, and a quad as
# glTF (.gltf with an embedded buffer, .glb); camera, environment rotation and
# --side-by-side; bad meshes and options (exit 1 / 2, the message names the file and line
# or glTF item, nothing written, no temporary left behind). Untrained bundle.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
"$NBRDF" bundle init bundle --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
params=(--alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9,0.6,0.5 --albedo 0.7 --sigma-t 1)
"$NBRDF" bake --bundle bundle "${params[@]}" -o c.exr >/dev/null 2>&1
torus="$NBRDF_SOURCE_DIR/scripts/mesh-torus.py"
python3 "$torus" t.obj --rings 16 --sides 12
python3 "$torus" ta.ply --rings 16 --sides 12
python3 "$torus" tb.ply --rings 16 --sides 12 --binary
# A unit quad in y = 0 facing +y, as glTF with a base64 buffer and as .glb.
python3 - <<'PY'
import base64, json, struct
pos = struct.pack("<12f", -1, 0, 1, 1, 0, 1, 1, 0, -1, -1, 0, -1)
uv = struct.pack("<8f", 0, 1, 1, 1, 1, 0, 0, 0)
idx = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
data = pos + uv + idx + b"\0" * 4  # 96 bytes: .glb chunks end on 4-byte boundaries
doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
       "nodes": [{"mesh": 0, "name": "Quad"}],
       "meshes": [{"name": "Quad", "primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1},
                                                    "indices": 2}]}],
       "buffers": [{"byteLength": len(data)}],
       "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                       {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                       {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
       "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                      "min": [-1, 0, -1], "max": [1, 0, 1]},
                     {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                     {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]}
emb = json.loads(json.dumps(doc))
emb["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
open("q.gltf", "w").write(json.dumps(emb))
j = json.dumps(doc).encode()
j += b" " * (-len(j) % 4)
glb = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(j) + 8 + len(data))
glb += struct.pack("<I4s", len(j), b"JSON") + j + struct.pack("<I4s", len(data), b"BIN\0") + data
open("q.glb", "wb").write(glb)
del emb["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"]
open("nouv.gltf", "w").write(json.dumps(emb))
PY
small=(--width 24 --height 16 --spp 2 --bundle bundle)

for m in t.obj ta.ply tb.ply q.gltf q.glb; do
  expect_exit 0 "$NBRDF" render c.exr --mesh $m -o $m.exr --png $m.png "${small[@]}" --progress=json
  check "$m: json done line with triangles" grep -Eq '"event":"done","width":24,.*"triangles":[1-9]' "$TMP/out"
  check "$m: png 24x16" bash -c "oiiotool --info $m.png | grep -q '24 x  *16, 3 channel, uint8 png'"
done
check "OBJ and PLY give the same torus" idiff -q -fail 1e-5 -failrelative 1e-4 t.obj.exr ta.ply.exr
check "ASCII and binary PLY give the same torus" idiff -q -fail 1e-5 -failrelative 1e-4 ta.ply.exr tb.ply.exr
check "the torus is not the background" bash -c "! idiff -q -fail 1e-3 t.obj.exr q.gltf.exr"
# Camera, field of view, environment rotation: images differ from the default ones.
expect_exit 0 "$NBRDF" render c.exr --mesh t.obj -o cam.exr "${small[@]}" --camera-pos 0,3,0.01 \
  --camera-target 0,0,0 --camera-up 0,0,-1 --fov 60
check "camera moves the view" bash -c "! idiff -q -fail 1e-3 cam.exr t.obj.exr"
# An environment red to the west, blue to the east: turning it shows in the background.
oiiotool --pattern fill:left=2,0,0:right=0,0,2 16x8 3 -d float -o env.exr
for r in 0 90 360; do
  expect_exit 0 "$NBRDF" render c.exr --mesh t.obj -o rot$r.exr "${small[@]}" --env env.exr --env-rotation $r
done
check "env rotation changes the image" bash -c "! idiff -q -fail 1e-3 rot90.exr rot0.exr"
check "a full turn is no turn" idiff -q -fail 1e-4 -failrelative 1e-3 rot360.exr rot0.exr
# Side by side: twice as wide, the left half the neural image.
expect_exit 0 "$NBRDF" render c.exr --mesh t.obj -o sbs.exr --png sbs.png "${small[@]}" --side-by-side "${params[@]}"
check "side by side 48x16" bash -c "oiiotool --info sbs.png | grep -q '48 x  *16, 3 channel'"
check "left half is the neural image" bash -c \
  "oiiotool sbs.exr --cut 24x16+0+0 -o left.exr && idiff -q -fail 1e-5 left.exr t.obj.exr"

# Bad meshes: exit 1, the message names the file and line or glTF item; nothing written.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > nouv.obj
expect_exit 1 "$NBRDF" render c.exr --mesh nouv.obj -o x.exr "${small[@]}"
expect_stderr "nouv.obj:4: face corner '1' has no texture coordinate" "$NBRDF" render c.exr --mesh nouv.obj -o x.exr "${small[@]}"
expect_stderr "nouv.gltf: mesh 0 ('Quad') primitive 0 has no TEXCOORD_0" "$NBRDF" render c.exr --mesh nouv.gltf -o x.exr "${small[@]}"
head -c 300 tb.ply > cut.ply
expect_stderr "cut.ply: binary data ends at byte" "$NBRDF" render c.exr --mesh cut.ply -o x.exr "${small[@]}"
expect_stderr "nothere.glb" "$NBRDF" render c.exr --mesh nothere.glb -o x.exr "${small[@]}"
echo solid > m.stl
expect_stderr "expected .gltf, .glb, .ply or .obj" "$NBRDF" render c.exr --mesh m.stl -o x.exr "${small[@]}"
# Usage errors: exit 2.
expect_exit 2 "$NBRDF" render c.exr --mesh t.obj -o x.exr --camera-pos 1,2,3
expect_exit 2 "$NBRDF" render c.exr --mesh t.obj -o x.exr --camera-target 1,2,3
expect_exit 2 "$NBRDF" render c.exr --mesh t.obj -o x.exr --camera-pos 1,2 --camera-target 0,0,0
expect_exit 2 "$NBRDF" render c.exr --mesh t.obj -o x.exr --fov 180
expect_exit 2 "$NBRDF" render c.exr --mesh t.obj -o x.exr --scene plane
expect_exit 2 "$NBRDF" render c.exr --mesh t.obj -o x.exr --side-by-side
expect_exit 2 "$NBRDF" render c.exr --mesh t.obj -o x.exr --side-by-side --mode reference "${params[@]}"
expect_exit 1 "$NBRDF" render c.exr --mesh t.obj -o t.obj "${small[@]}"
expect_exit 1 "$NBRDF" render c.exr --mesh t.obj -o x.exr "${small[@]}" --camera-pos 0,0,0 --camera-target 0,0,0
check "no output after failures" test ! -e x.exr
check "no temporary files left" bash -c "! ls -a | grep -E '\\.tmp|~\$|\\.part'"
check "mesh untouched" test -s t.obj
finish
