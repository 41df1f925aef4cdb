"""Reads the active material's Principled BSDF into bake parameters (table: principled.py).

Each mapped socket gives a Reading: a constant (its value), an image (an Image Texture node
linked straight to it) or a procedural input (any other node: it needs the UV bake of
uv_bake.py before `nbrdf bake` can read it).
"""

from collections import namedtuple

import bpy

from . import principled

# kind: "value" (value: list of floats), "image" (value: an Image), "procedural" (value: the
# socket, baked through the UV map on request); notes: what the user should know; node: the
# Image Texture node's name (an image), for messages about its image.
Reading = namedtuple("Reading", "kind value socket notes node", defaults=(None,))


class MaterialError(Exception):
    pass


def find_principled(material):
    """The Principled BSDF feeding the active Material Output, else the first one; or None."""
    if material is None or not material.use_nodes or material.node_tree is None:
        return None
    nodes = material.node_tree.nodes
    for n in nodes:
        if n.type == "OUTPUT_MATERIAL" and n.is_active_output:
            links = n.inputs["Surface"].links
            if links and links[0].from_node.type == "BSDF_PRINCIPLED":
                return links[0].from_node
    for n in nodes:
        if n.type == "BSDF_PRINCIPLED":
            return n
    return None


def _socket(node, name):
    s = node.inputs.get(name)
    if s is None:
        raise MaterialError("Principled BSDF '%s' has no '%s' input (Blender %s)"
                            % (node.name, name, bpy.app.version_string))
    return s


def _read_socket(node, name):
    s = _socket(node, name)
    if s.is_linked:
        src = s.links[0].from_node
        if src.type == "TEX_IMAGE" and src.image is not None:
            return Reading("image", src.image, name, [], src.name)
        return Reading("procedural", s, name, [])
    v = s.default_value
    return Reading("value", list(v)[:3] if hasattr(v, "__len__") else [float(v)], name, [])


def read(material, version=None):
    """{parameter key: Reading} for the mapped parameters, plus general notes."""
    node = find_principled(material)
    if node is None:
        raise MaterialError("material '%s' has no Principled BSDF: set the parameters by hand"
                            % (material.name if material else "(none)"))
    version = version or bpy.app.version
    gen = principled.generation(version)
    out, notes = {}, []
    for key, src in principled.mapping(version).items():
        r = _read_socket(node, src.socket)
        if src.how == "base_color":
            r = _base_color(node, r)
        out[key] = r
    coat = _socket(node, principled.COAT_WEIGHT[gen])
    if not coat.is_linked and coat.default_value < 1.0:
        notes.append("%s %.3g has no counterpart: the layered BRDF always has its whole coat"
                     % (principled.COAT_WEIGHT[gen], coat.default_value))
    return out, notes


def _base_color(node, r):
    metal = _socket(node, principled.METALLIC)
    if metal.is_linked:
        return r._replace(notes=["Metallic is linked and not read: Base Color is R0"])
    m = float(metal.default_value)
    if r.kind == "value":
        return r._replace(value=principled.r0_constant(r.value, m))
    if m < 1.0:
        return r._replace(notes=["Metallic %.3g is not applied to a Base Color map: the map "
                                 "is R0" % m])
    return r
