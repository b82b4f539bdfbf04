"""Baked maps into Blender images named `<object>_<output>`: created or updated, packed
or saved as OpenEXR, and optionally shown by the object's material."""

import os

import bpy

DATA_OUTPUTS = {"thickness", "stretch", "area"}


def _linear_space():
    names = {
        item.identifier
        for item in bpy.types.ColorManagedInputColorspaceSettings.bl_rna.properties["name"].enum_items
    }
    return next((n for n in ("Linear Rec.709", "Linear") if n in names), None)


def store(obj, output, result, destination, folder):
    """The image `<object>_<output>` holding map `output` of `result`: packed into the
    .blend, or an OpenEXR file the library writes into `folder` (whole or not at all)."""
    name = f"{obj.name}_{output}"
    resolution = result.resolution
    image = bpy.data.images.get(name)
    if image is not None and tuple(image.size) != (resolution, resolution):
        bpy.data.images.remove(image)
        image = None
    if destination == "FOLDER":
        os.makedirs(folder, exist_ok=True)
        path = os.path.join(folder, f"{bpy.path.clean_name(name)}.exr")
        result.write_exr(output, path)
        if image is None:
            image = bpy.data.images.load(path)
            image.name = name
        else:
            image.filepath = path
            image.source = "FILE"
            image.reload()
    else:
        if image is not None and image.source != "GENERATED":
            # A file-backed image (an earlier bake to a folder) would pack its file.
            bpy.data.images.remove(image)
            image = None
        if image is None:
            image = bpy.data.images.new(name, resolution, resolution, alpha=True, float_buffer=True)
        image.pixels.foreach_set(result.image(output))
        image.file_format = "OPEN_EXR"
        image.pack()
    space = "Non-Color" if output in DATA_OUTPUTS else _linear_space()
    if space:
        image.colorspace_settings.name = space
    image.update()
    return image


def show_in_material(obj, image, uv_map):
    """Image Texture → Emission → a new active Material Output in the object's active
    material; the original nodes stay, the old output inactive. False without one."""
    material = obj.active_material
    if material is None:
        return False
    if material.node_tree is None:
        material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links

    def node(kind, name, location):
        found = nodes.get(name)
        if found is None:
            found = nodes.new(kind)
            found.name = found.label = name
            found.location = location
        return found

    coordinates = node("ShaderNodeUVMap", "sssbake UV", (-900, -600))
    coordinates.uv_map = uv_map
    texture = node("ShaderNodeTexImage", "sssbake diffuse", (-700, -600))
    texture.image = image
    emission = node("ShaderNodeEmission", "sssbake emission", (-400, -600))
    output = node("ShaderNodeOutputMaterial", "sssbake output", (-200, -600))
    links.new(coordinates.outputs["UV"], texture.inputs["Vector"])
    links.new(texture.outputs["Color"], emission.inputs["Color"])
    links.new(emission.outputs["Emission"], output.inputs["Surface"])
    for other in nodes:
        if other.type == "OUTPUT_MATERIAL":
            other.is_active_output = other == output
    return True
