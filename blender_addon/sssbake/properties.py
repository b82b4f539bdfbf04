"""What the panel sets, stored on the scene; the bake operator's properties mirror it."""

import bpy

from . import native

# The presets offered when the library cannot be loaded, so the panel still registers
# and the bake reports the missing library; with the library, its own list is used.
PRESETS = [
    ("skin1", "Skin 1", "Jensen et al. 2001, measured skin"),
    ("skin2", "Skin 2", "Jensen et al. 2001, measured skin"),
    ("skin3layer", "Skin, three layers", "Donner & Jensen 2005"),
    ("deon-skin", "Skin, six Gaussians", "d'Eon & Luebke 2007"),
    ("marble", "Marble", "Jensen et al. 2001"),
    ("apple", "Apple", "Jensen et al. 2001"),
    ("potato", "Potato", "Jensen et al. 2001"),
    ("ketchup", "Ketchup", "Jensen et al. 2001"),
    ("wholemilk", "Whole milk", "Jensen et al. 2001"),
    ("skimmilk", "Skim milk", "Jensen et al. 2001"),
    ("cream", "Cream", "Jensen et al. 2001"),
    ("chicken1", "Chicken 1", "Jensen et al. 2001"),
    ("chicken2", "Chicken 2", "Jensen et al. 2001"),
    ("spectralon", "Spectralon", "Jensen et al. 2001"),
]
SOURCES = [
    ("PRINCIPLED", "From Principled BSDF", "Base Color and the subsurface inputs, read as Cycles reads them"),
    ("PRESET", "Preset", "A measured material"),
    ("LAYERS", "Custom layers", "A TOML file of layers (see the README)"),
]
ALBEDO_MAPPINGS = [
    ("CYCLES", "Like Cycles", "Colour to albedo by Cycles' own fit: the bake looks like Cycles' render"),
    (
        "PHYSICAL",
        "Physical",
        "Colour to albedo by the dipole: under uniform light the bake shows exactly the colour",
    ),
]
METHODS = [
    ("AUTO", "Auto", "Let the library choose, and say why"),
    ("BRUTE", "Exact", "The exact sum: the reference, slowest"),
    ("OCTREE", "Octree", "Hierarchical: near-exact, fast"),
    ("TEXTURE", "Texture space", "Separable blurs: fastest, a few percent off"),
    ("IMPORTANCE", "Monte Carlo", "Probe rays: noisy at low quality"),
]
QUALITIES = [
    ("DRAFT", "Draft", "4 light samples"),
    ("GOOD", "Good", "16 light samples"),
    ("FINAL", "Final", "64 light samples"),
]
QUALITY_SAMPLES = {"DRAFT": 4, "GOOD": 16, "FINAL": 64}
OUTPUTS = [
    ("SUBSURFACE", "Subsurface", "Exitance, W/m²"),
    ("IRRADIANCE", "Irradiance", "Transmitted irradiance, W/m²"),
    ("DIFFUSE", "Diffuse", "Diffuse radiance through the exit Fresnel"),
    ("THICKNESS", "Thickness", "Distance through the object, mm"),
    ("STRETCH", "Stretch", "Surface length per texel along u and v, mm"),
    ("AREA", "Area", "Surface area per texel, mm²"),
]
DESTINATIONS = [
    ("PACK", "Packed", "Pack the images into the .blend"),
    ("FOLDER", "Folder", "Save the images as OpenEXR files in a folder"),
]


def preset_items():
    """The library's presets as enum items, or PRESETS when it cannot be loaded."""
    try:
        return [(name, name, description) for name, description in native.presets()]
    except native.NativeError:
        return PRESETS


# The defaults when the library cannot be loaded; with the library, its own are used
# (sssbake_settings_default), so each default is defined once, in the library.
FALLBACK_DEFAULTS = {
    "resolution": 1024,
    "margin": 8,
    "outputs": {"SUBSURFACE", "IRRADIANCE", "DIFFUSE"},
    "quality": "GOOD",
}


def library_defaults():
    """The library's defaults for the settings the panel shows, or FALLBACK_DEFAULTS."""
    try:
        settings = native.default_settings()
        outputs = {name.upper() for i, name in enumerate(native.OUTPUTS) if settings.outputs & (1 << i)}
    except native.NativeError:
        return FALLBACK_DEFAULTS
    quality = next((q for q, samples in QUALITY_SAMPLES.items() if samples == settings.light_samples), "GOOD")
    return {
        "resolution": settings.resolution,
        "margin": settings.margin,
        "outputs": outputs,
        "quality": quality,
    }


def bake_properties(presets=PRESETS, defaults=FALLBACK_DEFAULTS):
    """The settings as property definitions, shared by the panel and the operator;
    `presets` are the preset enum's items and `defaults` the library's defaults
    (register() passes both from the library)."""
    return {
        "material_source": bpy.props.EnumProperty(name="Material", items=SOURCES, default="PRINCIPLED"),
        "preset": bpy.props.EnumProperty(name="Preset", items=presets, default="skin1"),
        "layers_file": bpy.props.StringProperty(name="Layers", subtype="FILE_PATH", default=""),
        "albedo_mapping": bpy.props.EnumProperty(
            name="Colour to Albedo",
            description="How a Principled BSDF's Base Color becomes the medium's albedo",
            items=ALBEDO_MAPPINGS,
            default="CYCLES",
        ),
        "resolution": bpy.props.IntProperty(
            name="Resolution", default=defaults["resolution"], min=1, soft_min=64, soft_max=8192
        ),
        "method": bpy.props.EnumProperty(name="Method", items=METHODS, default="AUTO"),
        "quality": bpy.props.EnumProperty(name="Quality", items=QUALITIES, default=defaults["quality"]),
        "outputs": bpy.props.EnumProperty(
            name="Outputs",
            items=OUTPUTS,
            options={"ENUM_FLAG"},
            default=defaults["outputs"],
        ),
        "uv_map": bpy.props.StringProperty(name="UV Map", description="Empty: the active UV map", default=""),
        "unwrap": bpy.props.BoolProperty(
            name="Unwrap", description="Make a new UV map `sssbake` (Smart UV Project) and bake into it"
        ),
        "destination": bpy.props.EnumProperty(name="Results", items=DESTINATIONS, default="PACK"),
        "folder": bpy.props.StringProperty(name="Folder", subtype="DIR_PATH", default="//sssbake"),
        "wire_material": bpy.props.BoolProperty(
            name="Show in Material",
            description="Add an Image Texture and Emission feeding a new active Material Output; the original nodes stay",
            default=False,
        ),
        "margin": bpy.props.IntProperty(name="Margin", default=defaults["margin"], min=0, max=64),
    }


SETTING_NAMES = tuple(bake_properties())


class SSSBAKE_PG_settings(bpy.types.PropertyGroup):
    __annotations__ = bake_properties()
