"""Per-material bake settings, saved in the .blend file."""

import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, IntVectorProperty, PointerProperty,
                       StringProperty)

from . import principled
from .params import PARAMS, SIGMA_T_MAX


def _param_annotations():
    """For each parameter: <key>_source (value or image), <key>_image, <key>_value."""
    ann = {}
    for p in PARAMS:
        items = [("VALUE", "Value", "A constant"), ("IMAGE", "Image", "An image datablock")]
        if p.key in principled.mapped_keys():
            items.append(("MATERIAL", "Material",
                          "From the material's Principled BSDF (docs/BLENDER.md, \"From the "
                          "material\"): its value or the Image Texture linked to it"))
        ann[p.key + "_source"] = EnumProperty(name=p.label + " Source", items=items,
                                              default="VALUE")
        ann[p.key + "_image"] = PointerProperty(
            name=p.label + " Image", type=bpy.types.Image,
            description=p.description + ". Any image: on disk, packed or generated")
        if p.colour:
            ann[p.key + "_value"] = FloatVectorProperty(
                name=p.label, subtype="COLOR", size=3, min=0.0, max=1.0, default=p.default,
                description=p.description)
        else:
            ann[p.key + "_value"] = FloatProperty(
                name=p.label, min=0.0, soft_max=p.soft_max, default=p.default, precision=3,
                description=p.description)
    return ann


class NBRDF_MaterialSettings(bpy.types.PropertyGroup):
    __annotations__ = dict(
        _param_annotations(),
        roughness=EnumProperty(
            name="Roughness", default="PERCEPTUAL",
            items=[("PERCEPTUAL", "Perceptual (Blender)",
                    "Roughness r as in Blender's Principled BSDF; the bake uses alpha = r²"),
                   ("ALPHA", "GGX Alpha", "GGX alpha as in the paper and pbrt")]),
        colour_maps=EnumProperty(
            name="Colour Maps", default="AUTO",
            description="Colour space of 8-bit reflectance and albedo maps (float maps are "
                        "linear and never converted)",
            items=[("AUTO", "From Image", "sRGB images are linearised, Non-Color/Linear/Raw "
                                          "images are not"),
                   ("SRGB", "sRGB", "Linearise with the sRGB curve"),
                   ("LINEAR", "Linear", "No conversion")]),
        eta_range=FloatVectorProperty(
            name="IOR Range", size=2, default=(1.0, 2.0), min=1.0,
            description="8-bit IOR maps: 0 and 1 map to these IORs"),
        sigma_t_range=FloatVectorProperty(
            name="Optical Depth Range", size=2, default=(0.0, SIGMA_T_MAX), min=0.0,
            description="8-bit optical depth maps: 0 and 1 map to these depths"),
        range_policy=EnumProperty(
            name="Out of Range", default="CLAMP",
            items=[("CLAMP", "Clamp", "Clamp to the model's trained range; every input outside "
                                      "it is listed before the bake starts"),
                   ("REFUSE", "Refuse", "List every input outside the range, then stop, "
                                        "naming the image and texel")]),
        size_mode=EnumProperty(
            name="Resolution", default="AUTO",
            items=[("AUTO", "Largest Map", "The largest input image's size; the Size below "
                                           "when every input is a constant or procedural"),
                   ("CUSTOM", "Custom", "The Size below")]),
        size=IntVectorProperty(name="Size", size=2, default=(256, 256), min=1, max=65536,
                               description="Width and height of the latent texture in texels"),
        resample=BoolProperty(
            name="Resample Maps", default=True,
            description="Maps of another size than the texture are resampled bilinearly "
                        "(nbrdf bake --resample bilinear); off: such a bake is refused"),
        accuracy=EnumProperty(
            name="Accuracy", default="FAST",
            description="How closely the texture follows the physics of this material's own "
                        "BRDFs (nbrdf bake --accuracy; docs/BAKE.md measures the trade)",
            items=[("FAST", "Fast", "The universal networks: seconds"),
                   ("FITTED", "Fitted", "Latents fitted to the layered ground truth of the "
                                        "material's own BRDFs; any renderer decodes them"),
                   ("SPECIALISED", "Specialised",
                    "Also a decoder fine-tuned to the material, carried in the texture "
                    "(format version 2)"),
                   ("COMPACT", "Compact",
                    "As Specialised, then a few latent channels per colour channel and a "
                    "small decoder distilled for the material: fast to decode, a third of "
                    "the channels"),
                   ("AUTO", "Auto",
                    "The cheapest level whose held-out error meets the Target Error: Fast "
                    "is measured first, then Fitted and Specialised are tried within the "
                    "Budget (nbrdf bake --accuracy auto --max-error)")]),
        max_error=FloatProperty(
            name="Target Error", default=5.0, min=0.01, max=1000.0, precision=1,
            subtype="PERCENTAGE",
            description="Auto: the held-out lobe error (%, nbrdf verify's metric) the texture "
                        "must meet; the bake climbs levels until one does"),
        accuracy_result=StringProperty(
            name="Accuracy Result", default="",
            description="The level the last bake used and its held-out lobe error"),
        compact_channels=IntProperty(
            name="Latent Channels", default=8, min=1, max=8,
            description="Compact: latent channels per colour channel (nbrdf bake --compact)"),
        budget=FloatProperty(
            name="Budget", default=0.0, min=0.0, max=1e7, unit="TIME_ABSOLUTE",
            description="Fitted, Specialised, Compact and Auto (each level tried): seconds "
                        "of ground truth and fitting (about the time on one free core; 0: the level's default, "
                        "120 s / 300 s / 400 s). The result does not depend on the machine's "
                        "load"),
        bake_uv=BoolProperty(
            name="Bake Through UV Map", default=False,
            description="Inputs from the material that come from nodes other than an Image "
                        "Texture are baked to images over the active object's UV map with "
                        "Cycles (EMIT) first"),
        verify=BoolProperty(
            name="Verify", default=False,
            description="After the bake, check 16 texels against the physics (nbrdf verify "
                        "--texels 16 --spp 16: about half a CPU-second per distinct texel) "
                        "and show the lobe error"),
        verify_median=FloatProperty(name="Median Lobe Error", default=-1.0,
                                    description="Median lobe error (%) of the last verify"),
        verify_worst=FloatProperty(name="Worst Lobe Error", default=-1.0,
                                   description="Worst lobe error (%) of the last verify"),
        verify_texels=IntProperty(name="Verified Texels", default=0),
        output=StringProperty(
            name="Output", subtype="FILE_PATH", default="//latent/{material}.exr",
            description="Latent texture to write ({material}: the material's name; // is "
                        "the .blend file's folder). With a tiled (UDIM) input it is a tile "
                        "set: <UDIM> is added before .exr unless the path has a tile token"),
        storage=EnumProperty(
            name="Storage", default="HALF",
            items=[("HALF", "Half", "16-bit floats (half the size)"),
                   ("FLOAT", "Float", "32-bit floats")]),
        mip_levels=EnumProperty(
            name="Mip Levels", default="FULL",
            items=[("FULL", "Full Chain", "Every mip level (latents averaged)"),
                   ("ONE", "Level 0 Only", "No mip levels")]),
        tile=IntProperty(name="Tile Size", default=64, min=8, max=1024,
                         description="Tile edge of the OpenEXR file in texels"),
        preview=BoolProperty(
            name="Preview Render", default=True,
            description="After the bake, render the texture on a sphere with 'nbrdf render' "
                        "(when the nbrdf executable has it) and load it as a second image"),
        preview_size=IntProperty(name="Preview Size", default=128, min=16, max=2048,
                                 description="Width and height of the preview in pixels"),
        preview_spp=IntProperty(name="Preview Samples", default=8, min=1, max=4096,
                                description="Samples per pixel of the preview"),
        preview_image=PointerProperty(name="Preview", type=bpy.types.Image,
                                      description="The preview render of the last bake"),
        range_report=StringProperty(
            name="Range Report", default="",
            description="The last bake's inputs outside the model's trained range, one per "
                        "line (nbrdf bake's range report)"),
        result=PointerProperty(name="Result", type=bpy.types.Image,
                               description="The latent texture of the last bake"),
        farm_plan=StringProperty(
            name="Farm Plan", subtype="DIR_PATH", default="//farm/{material}",
            description="Folder of the farm plan for a tiled (UDIM) bake (Write Farm Plan: "
                        "nbrdf farm slurm --plan; {material}: its name, // the .blend file's "
                        "folder). Its inputs/ holds the maps that exist only in Blender"),
        lookdev_size=IntVectorProperty(
            name="Preview Object Size", size=2, default=(256, 256), min=16, max=4096,
            description="Width and height of the Preview Object render in pixels"),
        lookdev_spp=IntProperty(name="Samples", default=16, min=1, max=4096,
                                description="Samples per pixel of the Preview Object render"),
        lookdev_turntable=BoolProperty(
            name="Turntable", default=False,
            description="Render several frames, the environment turned a full circle over "
                        "them (an image sequence)"),
        lookdev_frames=IntProperty(name="Frames", default=8, min=2, max=360,
                                   description="Turntable frames"),
        lookdev_image=PointerProperty(name="Object Preview", type=bpy.types.Image,
                                      description="The last Preview Object render"),
        farm_report=StringProperty(
            name="Farm Plan Report", default="",
            description="What the last Write Farm Plan wrote and how to submit it"),
    )


classes = (NBRDF_MaterialSettings,)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Material.nbrdf_bake = PointerProperty(type=NBRDF_MaterialSettings)


def unregister():
    del bpy.types.Material.nbrdf_bake
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
