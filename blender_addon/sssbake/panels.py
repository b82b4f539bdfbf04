"""The panel, in the Properties editor (Object tab) and in the 3-D view's sidebar."""

import textwrap

import bpy


def draw_settings(layout, context, settings):
    layout.use_property_split = True
    layout.use_property_decorate = False
    layout.prop(settings, "material_source")
    if settings.material_source == "PRESET":
        layout.prop(settings, "preset")
    elif settings.material_source == "LAYERS":
        layout.prop(settings, "layers_file")
    else:
        layout.prop(settings, "albedo_mapping")
    layout.prop(settings, "resolution")
    layout.prop(settings, "method")
    layout.prop(settings, "quality")
    layout.prop(settings, "margin")
    layout.prop(settings, "max_memory")
    column = layout.column(heading="Outputs")
    column.prop(settings, "outputs")
    layout.prop(settings, "unwrap")
    if settings.unwrap:
        layout.prop(settings, "unwrap_method")
        layout.prop(settings, "redo_unwrap")
    elif context.active_object is not None and context.active_object.type == "MESH":
        layout.prop_search(settings, "uv_map", context.active_object.data, "uv_layers")
    else:
        layout.prop(settings, "uv_map")
    layout.prop(settings, "destination")
    if settings.destination == "FOLDER":
        layout.prop(settings, "folder")
        if settings.folder.startswith("//") and not bpy.data.filepath:
            layout.label(text="Save the .blend first: // is relative to it", icon="ERROR")
    layout.prop(settings, "wire_material")
    if settings.wire_material:
        layout.prop(settings, "copy_shared_materials")
    header, body = layout.panel("sssbake_advanced", default_closed=True)
    header.label(text="Advanced")
    if body is not None:
        for name in ADVANCED:
            body.prop(settings, name)
    selected = [o.name for o in context.selected_objects if o.type == "MESH"]
    layout.label(text=f"Targets: {', '.join(selected) or 'select mesh objects'}")
    layout.operator("sssbake.bake", icon="RENDER_STILL")


class InObjectProperties:
    """Placed in the Properties editor's Object tab (each panel's id is its class name)."""

    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "object"


class InSidebar:
    """Placed in the 3-D view's sidebar, in a tab of its own."""

    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "sssbake"


class SubsurfacePanel:
    """The panel's content, wherever it is shown."""

    bl_label = "Subsurface Bake"

    def draw(self, context):
        draw_settings(self.layout, context, context.scene.sssbake)


class SSSBAKE_PT_properties(SubsurfacePanel, InObjectProperties, bpy.types.Panel):
    pass


class SSSBAKE_PT_sidebar(SubsurfacePanel, InSidebar, bpy.types.Panel):
    pass


# The library's settings offered as they are (properties.advanced_settings), set by register().
ADVANCED = ()

# Why the library cannot be used, when register() found it so.
MISSING = ""


class MissingLibraryPanel:
    """In place of the settings when the sssbake package cannot be used: what is wrong."""

    bl_label = "Subsurface Bake"

    def draw(self, _context):
        column = self.layout.column()
        column.label(text="The sssbake library cannot be used:", icon="ERROR")
        for line in textwrap.wrap(MISSING, 60):
            column.label(text=line)


class SSSBAKE_PT_missing_properties(MissingLibraryPanel, InObjectProperties, bpy.types.Panel):
    pass


class SSSBAKE_PT_missing_sidebar(MissingLibraryPanel, InSidebar, bpy.types.Panel):
    pass


MISSING_PANELS = (SSSBAKE_PT_missing_properties, SSSBAKE_PT_missing_sidebar)
