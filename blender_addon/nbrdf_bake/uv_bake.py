"""Bakes one node input of a material to an image over the object's active UV map, with
Blender's own Cycles EMIT bake, so procedural inputs can go to `nbrdf bake`.

The node tree and the scene are changed only for the bake and restored afterwards (a
temporary Emission shader on the active Material Output, a temporary active Image Texture
node; render engine and samples): what the user sees after the bake is what was there before.
"""

import bpy
import numpy as np

UNBAKED = -1.0  # never a valid parameter (the bake refuses negative values)


class UVBakeError(Exception):
    pass


def check_object(obj, material):
    if obj is None or obj.type != "MESH":
        raise UVBakeError("Bake Through UV Map needs an active mesh object using material '%s'"
                          % material.name)
    if material.name not in [s.material.name for s in obj.material_slots if s.material]:
        raise UVBakeError("object '%s' does not use material '%s' (Bake Through UV Map bakes "
                          "over the active object)" % (obj.name, material.name))
    if not obj.data.uv_layers:
        raise UVBakeError("object '%s' has no UV map (Bake Through UV Map needs one)" % obj.name)


def _active_output(tree):
    for n in tree.nodes:
        if n.type == "OUTPUT_MATERIAL" and n.is_active_output:
            return n
    for n in tree.nodes:
        if n.type == "OUTPUT_MATERIAL":
            return n
    raise UVBakeError("the material has no Material Output node")


def bake_socket(context, obj, material, socket, name, width, height, fill=True, uv_map=None):
    """A new float image (Non-Color, width x height) holding what `socket` receives over
    `uv_map` (a UV map's name; default: the active one); texels outside
    the UV islands hold the mean of the others (fill), or UNBAKED. The UV map is Blender's
    bake's own uv_layer choice: the object's active UV map is never changed."""
    check_object(obj, material)
    uv_layers = obj.data.uv_layers
    if uv_map and uv_layers.get(uv_map) is None:
        raise UVBakeError("object '%s' has no UV map '%s' (it has %s)"
                          % (obj.name, uv_map, ", ".join("'%s'" % u.name for u in uv_layers)))
    return _bake_socket(context, obj, material, socket, name, width, height, fill, uv_map or "")


def _bake_socket(context, obj, material, socket, name, width, height, fill, uv_map):
    if not socket.is_linked:
        raise UVBakeError("%s is not linked to a node" % socket.name)
    tree = material.node_tree
    out = _active_output(tree)
    surface = out.inputs["Surface"]
    before = [l.from_socket for l in surface.links]
    image = bpy.data.images.new(name, width, height, alpha=False, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    # Texels outside every UV island (and its margin) are not baked: marked here, filled
    # after the bake with the mean of the baked ones, so they neither read as 0 (a roughness
    # the model clamps, with a warning) nor stand out in the texture's mips.
    image.pixels.foreach_set(np.full(width * height * 4, UNBAKED, np.float32))
    scene = context.scene
    saved = (scene.render.engine, scene.cycles.samples, scene.cycles.use_denoising,
             scene.render.bake.use_selected_to_active, tree.nodes.active,
             context.view_layer.objects.active, obj.select_get())
    emit = tree.nodes.new("ShaderNodeEmission")
    tex = tree.nodes.new("ShaderNodeTexImage")
    others = []  # (tree, its active node, the scratch node made active in it)
    scratch = None
    try:
        # Blender bakes every material of the object, each into its active texture node or,
        # when none is marked, its first Image Texture node: for another material that may
        # be the nbrdf latent texture (add_image_node), a multilayer EXR that Blender 3.4's
        # bake overruns (valgrind: 8 bytes past a RenderPass; crashes later) and overwrites.
        # Each other material bakes into one throwaway image instead.
        for slot in obj.material_slots:
            m = slot.material
            if m is None or m == material or not m.use_nodes or m.node_tree is None:
                continue
            if any(o[0] == m.node_tree for o in others):
                continue
            if scratch is None:
                scratch = bpy.data.images.new("nbrdf bake scratch", 1, 1, float_buffer=True)
            node = m.node_tree.nodes.new("ShaderNodeTexImage")
            node.image = scratch
            others.append((m.node_tree, m.node_tree.nodes.active, node))
            m.node_tree.nodes.active = node
        emit.inputs["Strength"].default_value = 1.0
        tree.links.new(socket.links[0].from_socket, emit.inputs["Color"])
        tree.links.new(emit.outputs["Emission"], surface)
        tex.image = image
        tree.nodes.active = tex
        scene.render.engine = "CYCLES"
        scene.cycles.samples = 1  # emission needs no light paths; one sample per texel
        # A Blender built without OpenImageDenoiser (Debian's 3.4) bakes black while
        # denoising is on; a bake of values needs no denoising anyway.
        scene.cycles.use_denoising = False
        scene.render.bake.use_selected_to_active = False
        context.view_layer.objects.active = obj
        obj.select_set(True)
        try:
            with context.temp_override(object=obj, active_object=obj, selected_objects=[obj]):
                # No margin from Blender: its Adjacent Faces margin (the default) blends
                # the UNBAKED marker into texels beside the islands, values no test can tell
                # from baked ones. The margin is grown below from baked texels only.
                bpy.ops.object.bake(type="EMIT", margin=0, use_clear=False, uv_layer=uv_map)
        except RuntimeError as e:
            raise UVBakeError("Blender's bake of material '%s', input '%s' from node '%s' "
                              "over '%s' failed: %s"
                              % (material.name, socket.name, socket.links[0].from_node.name,
                                 obj.name, str(e).strip())) from e
        _grow_margin(image, scene.render.bake.margin)
        if fill:
            _fill_unbaked(image)
    except BaseException:
        bpy.data.images.remove(image)
        raise
    finally:
        for other_tree, active, node in others:
            other_tree.nodes.remove(node)
            other_tree.nodes.active = active
        if scratch is not None:
            bpy.data.images.remove(scratch)
        tree.nodes.remove(emit)
        tree.nodes.remove(tex)
        for s in before:
            tree.links.new(s, surface)
        (scene.render.engine, scene.cycles.samples, scene.cycles.use_denoising,
         scene.render.bake.use_selected_to_active, active_node, active_obj, selected) = saved
        tree.nodes.active = active_node
        context.view_layer.objects.active = active_obj
        obj.select_set(selected)
    return image


def _grow_margin(image, texels):
    """Extends the islands by `texels` texels, each new texel the mean of its baked
    8-neighbours (Blender's Extend margin, whatever margin type the scene asks for)."""
    w, h = image.size
    px = np.empty(w * h * 4, np.float32)
    image.pixels.foreach_get(px)
    px = px.reshape(h, w, 4)
    baked = ~(px[..., :3] == UNBAKED).all(axis=2)
    for _ in range(max(0, int(texels))):
        if baked.all() or not baked.any():
            break
        total = np.zeros((h, w, 3), np.float64)
        count = np.zeros((h, w), np.int32)
        pad_v = np.pad(np.where(baked[..., None], px[..., :3], 0.0), ((1, 1), (1, 1), (0, 0)))
        pad_b = np.pad(baked, 1)
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                if dy or dx:
                    total += pad_v[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]
                    count += pad_b[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]
        grow = ~baked & (count > 0)
        if not grow.any():
            break
        px[grow, :3] = total[grow] / count[grow][:, None]
        baked |= grow
    image.pixels.foreach_set(px.ravel())


def _fill_unbaked(image):
    px = np.empty(len(image.pixels), np.float32)
    image.pixels.foreach_get(px)
    px = px.reshape(-1, 4)
    unbaked = (px[:, :3] == UNBAKED).all(axis=1)
    if unbaked.all():
        raise UVBakeError("the bake of '%s' covered no texel (is the UV map empty?)" % image.name)
    if unbaked.any():
        px[unbaked, :3] = px[~unbaked, :3].mean(axis=0)
        image.pixels.foreach_set(px.ravel())
