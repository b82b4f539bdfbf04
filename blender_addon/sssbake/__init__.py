"""sssbake for Blender: bakes subsurface scattering of the selected objects into images,
through the sssbake Python package (the wheel blender_manifest.toml lists, which Blender
installs with the extension). No physics lives here: the add-on moves Blender's data across."""

import bpy

from . import binding, operators, panels, properties

CLASSES = (
    properties.SSSBAKE_PG_settings,
    operators.SSSBAKE_OT_bake,
    panels.SSSBAKE_PT_properties,
    panels.SSSBAKE_PT_sidebar,
)

# What register() registered: CLASSES, or, without a usable library, the panels that say why.
_registered = ()


def register():
    global _registered
    # The settings, their defaults and ranges are the library's, read here rather than at
    # import; without the library the panel says what is missing and offers no bake.
    try:
        settings, defaults = properties.library()
    except binding.Error as error:
        panels.MISSING = str(error)
        _registered = panels.MISSING_PANELS
        for cls in _registered:
            bpy.utils.register_class(cls)
        return
    definitions = properties.bake_properties(settings, defaults)
    properties.SSSBAKE_PG_settings.__annotations__ = definitions
    properties.SETTING_NAMES = tuple(definitions)
    panels.ADVANCED = tuple(s["name"] for s in properties.advanced_settings(settings))
    operators.SSSBAKE_OT_bake.__annotations__ = properties.operator_properties(settings, defaults)
    _registered = CLASSES
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.sssbake = bpy.props.PointerProperty(type=properties.SSSBAKE_PG_settings)
    bpy.types.VIEW3D_MT_object.append(operators.menu_entry)


def unregister():
    global _registered
    if _registered == CLASSES:
        operators.cancel_running()
        bpy.types.VIEW3D_MT_object.remove(operators.menu_entry)
        del bpy.types.Scene.sssbake
    for cls in reversed(_registered):
        bpy.utils.unregister_class(cls)
    _registered = ()
