"""nbrdf Bake: bakes layered-BRDF parameters into latent textures with the nbrdf CLI.

Only registration lives here; nothing heavy runs at import (see docs/BLENDER.md).
"""

bl_info = {
    "name": "nbrdf Bake",
    "author": "nbrdf",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Material > nbrdf Latent Bake",
    "description": "Bake layered BRDF parameter maps into neural latent textures (nbrdf bake)",
    "category": "Material",
}

from . import lookdev, operators, panels, preferences, properties, queue  # noqa: E402

_modules = (preferences, properties, operators, queue, lookdev, panels)


def register():
    for m in _modules:
        m.register()


def unregister():
    for m in reversed(_modules):
        m.unregister()
