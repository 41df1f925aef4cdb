"""The Principled BSDF's sockets -> the six layered parameters, without bpy.

One table per Blender generation (3.x and 4.x renamed the coat sockets); docs/BLENDER.md,
"From the material", prints the same table. What has no counterpart is listed too, so the
panel and the docs can say what the user sets by hand.
"""

from collections import namedtuple

# socket: the Principled BSDF input read; how: "roughness" (Blender's perceptual roughness r,
# baked with --roughness perceptual, so alpha = r^2), "value" (used as is) or "base_color"
# (R0 from Base Color and Metallic, below).
Source = namedtuple("Source", "socket how")

MAPPING = {
    3: {
        "alpha1": Source("Clearcoat Roughness", "roughness"),
        "eta": Source("IOR", "value"),
        "alpha2": Source("Roughness", "roughness"),
        "r0": Source("Base Color", "base_color"),
    },
    4: {
        "alpha1": Source("Coat Roughness", "roughness"),
        "eta": Source("Coat IOR", "value"),
        "alpha2": Source("Roughness", "roughness"),
        "r0": Source("Base Color", "base_color"),
    },
}

# Read for a note only: the layered BRDF always has its whole coat.
COAT_WEIGHT = {3: "Clearcoat", 4: "Coat Weight"}
METALLIC = "Metallic"
# Reflectance at normal incidence of Blender's dielectric base (Specular 0.5 in 3.x; IOR 1.5
# in 4.x): what Metallic = 0 gives.
DIELECTRIC_F0 = 0.04

# The slab between coat and base has no socket in the Principled BSDF.
BY_HAND = ("albedo", "sigma_t")


def generation(version):
    """3 for Blender 3.x (and older), 4 for 4.x and later."""
    return 4 if tuple(version)[0] >= 4 else 3


def mapping(version):
    return MAPPING[generation(version)]


def mapped_keys():
    """The parameters a material can give (the same for every generation)."""
    return tuple(MAPPING[3])


def r0_constant(base_color, metallic):
    """R0 of a constant Base Color and Metallic: DIELECTRIC_F0 mixed toward the colour."""
    m = min(1.0, max(0.0, float(metallic)))
    return [DIELECTRIC_F0 * (1.0 - m) + float(c) * m for c in list(base_color)[:3]]


def table_rows(version):
    """(parameter, socket, what it becomes) for the docs and the panel's tooltips."""
    gen = generation(version)
    rows = []
    for key, src in MAPPING[gen].items():
        if src.how == "roughness":
            what = "r as typed, baked with the perceptual convention (alpha = r^2)"
        elif src.how == "base_color":
            what = ("mix(%.2f, Base Color, Metallic) for constants; an image is R0 itself"
                    % DIELECTRIC_F0)
        else:
            what = "as is"
        rows.append((key, src.socket, what))
    rows.append(("(none)", COAT_WEIGHT[gen], "no counterpart: the coat is always whole"))
    for key in BY_HAND:
        rows.append((key, "(none)", "set by hand"))
    return rows
