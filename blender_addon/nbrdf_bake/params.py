"""The six parameters of the bake, as the CLI names them (docs/BAKE.md), without bpy."""

from collections import namedtuple

Param = namedtuple("Param", "key flag label colour default soft_max description")

# The trained optical-depth maximum: NBRDF_BAKE_SIGMA_T_MAX of include/nbrdf/bake.h
# (tests/blender/test_conventions.sh keeps the two equal).
SIGMA_T_MAX = 5.0

PARAMS = (
    Param("alpha1", "--alpha1", "Coat Roughness", False, 0.1, 1.0,
          "Top coat GGX roughness (see Roughness convention)"),
    Param("eta", "--eta", "Coat IOR", False, 1.5, 2.0,
          "Top coat index of refraction; 8-bit maps map [0, 1] to the IOR range"),
    Param("alpha2", "--alpha2", "Base Roughness", False, 0.3, 1.0,
          "Bottom conductor GGX roughness (see Roughness convention)"),
    Param("r0", "--r0", "Base Reflectance", True, (0.9, 0.6, 0.5), 1.0,
          "Bottom conductor Schlick reflectance at normal incidence (colour)"),
    Param("albedo", "--albedo", "Slab Albedo", True, (0.8, 0.8, 0.8), 1.0,
          "Single-scattering albedo of the slab between the interfaces (colour)"),
    Param("sigma_t", "--sigma-t", "Slab Optical Depth", False, 1.0, SIGMA_T_MAX,
          "Optical depth of the slab (unit thickness); 8-bit maps map [0, 1] to its range"),
)


def number(v):
    """A float32 property value as text that parses back to the same float32."""
    return "%.9g" % v


def constant(values):
    """'v' for a grey constant (keeps an all-grey bake mono), else 'r,g,b'."""
    values = list(values)
    if all(v == values[0] for v in values):
        return number(values[0])
    return ",".join(number(v) for v in values)


def range_lines(events):
    """The CLI's range report ("range" events) in the panel's words: each parameter by its
    label here, in the units the add-on passed (perceptual roughness, IOR)."""
    labels = {p.key: p.label for p in PARAMS}
    out = []
    for ev in events:
        message = str(ev.get("message", ""))
        head, sep, rest = message.partition("): ")
        key = str(ev.get("parameter", ""))
        out.append("%s: %s" % (labels.get(key, key), rest) if sep else message)
    return out
