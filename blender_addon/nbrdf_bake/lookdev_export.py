"""Exports what the look-dev preview renders (docs/BLENDER.md, "Preview Object"): the object as
glTF (+Y up, UVs, normals, modifiers applied), the scene camera as `nbrdf render` camera
options, and the world's Environment Texture image.

Blender is Z up, glTF and `nbrdf render` Y up: a point (x, y, z) becomes (x, z, -y).
Blender's equirectangular images put their centre column at +X; nbrdf's at -Z (Blender's +Y):
the environment is turned by ENV_ROTATION_BASE degrees so that the same image lights the
object from the same directions in both.
"""

import math
import os

import bpy

from .inputs import SetupError

# nbrdf shows image column s(d) + rotation / 360 in direction d; Blender shows column
# s(d) - 1/4 (Cycles' direction_to_equirectangular: u = 1/2 - atan2(y, x) / 2π).
ENV_ROTATION_BASE = -90.0


def to_yup(v):
    return (v[0], v[2], -v[1])


def export_object(obj, path):
    """Writes `obj` alone to `path` (.glb). Raises SetupError for an object the preview
    cannot show: not a mesh, or without a UV map."""
    if obj is None:
        raise SetupError("no active object to preview")
    if obj.type != "MESH":
        raise SetupError("'%s' is a %s, not a mesh: the preview renders meshes"
                         % (obj.name, obj.type.lower()))
    if not obj.data.uv_layers:
        raise SetupError("'%s' has no UV map: the latent texture is looked up by UV (add one: "
                         "UV Editing > Unwrap)" % obj.name)
    view_layer = bpy.context.view_layer
    selected = [o for o in view_layer.objects if o.select_get()]
    active = view_layer.objects.active
    try:
        for o in selected:
            o.select_set(False)
        obj.select_set(True)
        view_layer.objects.active = obj
        result = bpy.ops.export_scene.gltf(
            filepath=path, export_format="GLB", use_selection=True, export_texcoords=True,
            export_normals=True, export_materials="NONE", export_yup=True, export_apply=True,
            export_cameras=False, export_lights=False, export_animations=False)
    finally:
        obj.select_set(False)
        for o in selected:
            o.select_set(True)
        view_layer.objects.active = active
    if "FINISHED" not in result or not os.path.isfile(path):
        raise SetupError("the glTF export of '%s' failed" % obj.name)


def camera_args(scene, width, height):
    """`--camera-pos/--camera-target/--camera-up/--fov` for the scene camera (perspective);
    [] without one (nbrdf then frames the object)."""
    cam = scene.camera
    if cam is None or cam.type != "CAMERA" or cam.data.type != "PERSP":
        return []
    m = cam.matrix_world
    pos = m.translation
    forward = (m.to_3x3() @ _vec((0.0, 0.0, -1.0))).normalized()
    up = (m.to_3x3() @ _vec((0.0, 1.0, 0.0))).normalized()
    target = pos + forward
    d = cam.data
    fit = d.sensor_fit
    if fit == "AUTO":
        fit = "HORIZONTAL" if width >= height else "VERTICAL"
    half = math.tan(0.5 * d.angle)
    # Blender's angle spans the fitted dimension; nbrdf's --fov is vertical.
    if fit == "HORIZONTAL":
        half = half * height / float(width)
    fov = math.degrees(2.0 * math.atan(half))
    fmt = lambda v: "%.6g,%.6g,%.6g" % to_yup(v)  # noqa: E731
    return ["--camera-pos", fmt(pos), "--camera-target", fmt(target), "--camera-up", fmt(up),
            "--fov", "%.6g" % fov]


def _vec(t):
    from mathutils import Vector
    return Vector(t)


def environment_image(scene, folder):
    """The world's Environment Texture image as a file nbrdf can read, or None (no world, no
    such node, no image): on disk as it is, else (packed, generated) saved to `folder`."""
    world = scene.world
    if world is None or not world.use_nodes or world.node_tree is None:
        return None
    for node in world.node_tree.nodes:
        if node.type != "TEX_ENVIRONMENT" or node.image is None:
            continue
        im = node.image
        path = bpy.path.abspath(im.filepath) if im.filepath else ""
        if im.source == "FILE" and im.packed_file is None and path and os.path.isfile(path):
            return path
        copy = im.copy()
        try:
            out = os.path.join(folder, "environment.exr")
            copy.filepath_raw = out
            copy.file_format = "OPEN_EXR"
            copy.save()
        finally:
            bpy.data.images.remove(copy)
        return out if os.path.isfile(out) else None
    return None
