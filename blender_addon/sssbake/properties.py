"""What the panel sets, stored on the scene; the bake operator's properties mirror it."""

import bpy

from . import binding

SOURCES = [
    ("PRINCIPLED", "From Principled BSDF", "Base Color and the subsurface inputs, read as Cycles reads them"),
    ("PRESET", "Preset", "A measured material"),
    ("LAYERS", "Custom layers", "A TOML file of layers (see docs/materials.md)"),
]
ALBEDO_MAPPINGS = [
    ("CYCLES", "Like Cycles", "Colour to albedo by Cycles' own fit: the bake looks like Cycles' render"),
    (
        "PHYSICAL",
        "Physical",
        "Colour to albedo by the dipole: under uniform light the bake shows exactly the colour",
    ),
]
QUALITY_SAMPLES = {"DRAFT": 4, "GOOD": 16, "FINAL": 64}
QUALITIES = [
    (key, key.title(), f"{samples} light samples per texel") for key, samples in QUALITY_SAMPLES.items()
]
UNWRAP_METHODS = [
    (
        "XATLAS",
        "xatlas",
        "The library's xatlas, as `sssbake bake` unwraps: charts cut at creases and packed tight",
    ),
    ("SMART", "Smart UV Project", "Blender's Smart UV Project"),
]
DESTINATIONS = [
    ("PACK", "Packed", "Pack the images into the .blend, kept by a fake user"),
    ("FOLDER", "Folder", "Save the images as OpenEXR files in a folder; the images read them"),
]


GIB = 1 << 30


def library():
    """What the panel reads of the library: every setting (`sssbake.settings()`) by name and
    its other defaults (`sssbake.defaults()`). Raises binding.Error when the package cannot be
    used; then register() shows why instead of the settings."""
    return binding.settings(), binding.defaults()


# The library's settings the panel shows in its own terms (Quality for light samples, GiB
# for the memory limit, Unwrap for the UV policy), which a host's scene decides, or which
# would state no default; every other setting of a bake or an integrator is offered as it
# is under Advanced, so a setting the library adds appears there by itself.
OWN_TERMS = frozenset({"resolution", "margin", "method", "outputs", "light_samples", "max_memory", "uvs"})
# Blender's integer properties are 32-bit.
INT_LIMIT = (1 << 31) - 1


def advanced_settings(settings):
    """The library's settings offered as they are, in the library's order."""
    return [
        s
        for s in settings.values()
        if s["part"] not in ("scene", "writing")
        and s["default"] is not None
        and s["name"] not in OWN_TERMS
        and s["kind"] in ("count", "number", "switch", "choice")
    ]


def _label(name):
    return name.replace("_", " ").title()


def setting_property(setting):
    """A property for one of the library's settings: its doc (with its unit) as the
    tooltip, its default and its range."""
    unit = f" ({setting['unit']})" if setting["unit"] else ""
    common = {"name": _label(setting["name"]), "description": setting["doc"].rstrip(".") + unit}
    kind = setting["kind"]
    if kind == "count":
        low, high = max(setting["min"], -INT_LIMIT), min(setting["max"], INT_LIMIT)
        return bpy.props.IntProperty(default=setting["default"], min=low, max=high, **common)
    if kind == "number":
        bounds = {k: setting[k] for k in ("min", "max") if setting[k] is not None}
        return bpy.props.FloatProperty(default=setting["default"], precision=4, **bounds, **common)
    if kind == "switch":
        return bpy.props.BoolProperty(default=setting["default"], **common)
    return bpy.props.EnumProperty(items=_items(setting), default=setting["default"].upper(), **common)


def _items(setting):
    """A choice setting's names as enum items: the identifier in capitals, the name as the
    label, the library's line on it as the tooltip."""
    return [
        (name.upper(), name.replace("-", " ").title(), note)
        for name, note in zip(setting["names"], setting["notes"], strict=True)
    ]


def _path_options():
    # Blender 4.5 and later mark a path that may start with `//` (relative to the .blend).
    return {"PATH_SUPPORTS_BLEND_RELATIVE"} if bpy.app.version >= (4, 5, 0) else set()


def bake_properties(settings, defaults):
    """The settings as property definitions, shared by the panel and the operator, from
    the library's `settings` (by name) and `defaults` (see library())."""
    samples = settings["light_samples"]["default"]
    quality = next((q for q, count in QUALITY_SAMPLES.items() if count == samples), "GOOD")
    return {
        "material_source": bpy.props.EnumProperty(
            name="Material",
            description="Where the scattering medium comes from",
            items=SOURCES,
            default="PRINCIPLED",
        ),
        "preset": bpy.props.EnumProperty(
            name="Preset",
            description="A measured material from the library",
            items=[
                (name, name, note)
                for name, note in zip(settings["preset"]["names"], settings["preset"]["notes"], strict=True)
            ],
            default=defaults["preset"],
        ),
        "layers_file": bpy.props.StringProperty(
            name="Layers",
            description="A TOML file of layers (see docs/materials.md); `//` is relative to the .blend file",
            subtype="FILE_PATH",
            options=_path_options(),
            default="",
        ),
        "albedo_mapping": bpy.props.EnumProperty(
            name="Colour to Albedo",
            description="How a Principled BSDF's Base Color becomes the medium's albedo",
            items=ALBEDO_MAPPINGS,
            default="CYCLES",
        ),
        "resolution": bpy.props.IntProperty(
            name="Resolution",
            description="Size of each baked image, in texels per side (the images are square)",
            default=settings["resolution"]["default"],
            min=settings["resolution"]["min"],
            max=settings["resolution"]["max"],
            soft_min=64,
            soft_max=8192,
            subtype="PIXEL",
        ),
        "method": bpy.props.EnumProperty(
            name="Method",
            description="How the light under the skin is summed over the surface",
            items=_items(settings["method"]),
            default=settings["method"]["default"].upper(),
        ),
        "quality": bpy.props.EnumProperty(
            name="Quality",
            description="Light samples per texel for each light with a size and for the world ("
            + ", ".join(f"{key.title()} {n}" for key, n in QUALITY_SAMPLES.items())
            + ")",
            items=QUALITIES,
            default=quality,
        ),
        "outputs": bpy.props.EnumProperty(
            name="Outputs",
            description="The maps to bake, each an image `<object>_<output>`",
            items=_items(settings["outputs"]),
            options={"ENUM_FLAG"},
            default={name.upper() for name in settings["outputs"]["default"]},
        ),
        "uv_map": bpy.props.StringProperty(
            name="UV Map",
            description="The UV map to bake into, as it is; empty: the active UV map",
            default="",
        ),
        "unwrap": bpy.props.BoolProperty(
            name="Unwrap",
            description="Bake into a UV map `sssbake` of its own, made once (charts apart by twice "
            "the margin) and then kept, with any fixes made to it; the active UV map stays as it is",
        ),
        "unwrap_method": bpy.props.EnumProperty(
            name="Unwrap With",
            description="What makes the `sssbake` UV map",
            items=UNWRAP_METHODS,
            default="XATLAS",
        ),
        "redo_unwrap": bpy.props.BoolProperty(
            name="Unwrap Again",
            description="Make the `sssbake` UV map afresh, replacing the one an earlier bake made "
            "(and any fixes made to it)",
        ),
        "destination": bpy.props.EnumProperty(
            name="Results",
            description="Where the baked images are kept",
            items=DESTINATIONS,
            default="PACK",
        ),
        "folder": bpy.props.StringProperty(
            name="Folder",
            description="The folder for the OpenEXR files, made if missing; `//` is relative to "
            "the .blend file, which must then be saved",
            subtype="DIR_PATH",
            options=_path_options(),
            default="//sssbake",
        ),
        "wire_material": bpy.props.BoolProperty(
            name="Show in Material",
            description="Show the Diffuse map in the object's materials: an Image Texture and "
            "Emission feeding a new active Material Output; the original nodes stay",
            default=False,
        ),
        "copy_shared_materials": bpy.props.BoolProperty(
            name="Copy Shared Materials",
            description="Show in Material on a material other objects also use: give the baked "
            "object its own copy (the others keep the original); off: leave such materials "
            "as they are and say so",
            default=False,
        ),
        "margin": bpy.props.IntProperty(
            name="Margin",
            description="Texels grown around each UV island, in pixels, so filtering at the "
            "island's edge does not show the background",
            default=settings["margin"]["default"],
            min=settings["margin"]["min"],
            soft_max=64,
            subtype="PIXEL",
        ),
        "max_memory": bpy.props.FloatProperty(
            name="Memory Limit (GiB)",
            description="Memory each object's bake may hold, in GiB (2³⁰ bytes); the library "
            "estimates it before the bake starts and refuses a bake that would need more, "
            "saying what drives it, rather than running out of memory",
            default=defaults["max_memory_bytes"] / GIB,
            min=0.001,
            max=1024.0,
            soft_min=0.25,
            soft_max=256.0,
            step=100,
            precision=2,
        ),
        **{s["name"]: setting_property(s) for s in advanced_settings(settings)},
    }


def operator_properties(settings, defaults):
    """The settings as the operator's properties: as the panel's, but never remembered from
    one call to the next (SKIP_SAVE), so a bake from the interface takes the panel's
    settings and a script's keywords apply to its own call only."""
    properties = {}
    for name, definition in bake_properties(settings, defaults).items():
        keywords = dict(definition.keywords)
        keywords["options"] = set(keywords.get("options", {"ANIMATABLE"})) | {"SKIP_SAVE"}
        properties[name] = definition.function(**keywords)
    return properties


# The settings' names, set by register() with the properties themselves.
SETTING_NAMES = ()


class SSSBAKE_PG_settings(bpy.types.PropertyGroup):
    """The panel's settings; register() gives it its properties, read from the library."""
