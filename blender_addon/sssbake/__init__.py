"""sssbake for Blender: bakes subsurface scattering of the selected objects into images,
through the sssbake Python package (the wheel blender_manifest.toml lists, which Blender
installs with the extension). No physics lives here: the add-on moves Blender's data across."""

import bpy

from . import operators, panels, properties

CLASSES = (
    properties.SSSBAKE_PG_settings,
    operators.SSSBAKE_OT_bake,
    panels.SSSBAKE_PT_properties,
    panels.SSSBAKE_PT_sidebar,
)


def register():
    # The preset list and the defaults are the library's when it loads; read here
    # rather than at import.
    presets, defaults = properties.preset_items(), properties.library_defaults()
    properties.SSSBAKE_PG_settings.__annotations__ = properties.bake_properties(presets, defaults)
    operators.SSSBAKE_OT_bake.__annotations__ = properties.operator_properties(presets, defaults)
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.sssbake = bpy.props.PointerProperty(type=properties.SSSBAKE_PG_settings)
    bpy.types.VIEW3D_MT_object.append(operators.menu_entry)


def unregister():
    operators.cancel_running()
    bpy.types.VIEW3D_MT_object.remove(operators.menu_entry)
    del bpy.types.Scene.sssbake
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
