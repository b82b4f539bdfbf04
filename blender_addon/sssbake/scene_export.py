"""The Blender scene as the library takes it: evaluated meshes (modifiers applied) as flat
world-space arrays with each triangle's material and the UV sets their textures read, lights
and the world colour in Blender's own units, and materials slot by slot. Only data moves
here; every conversion of units and physics happens in the library."""

import math

import bpy
import numpy as np

from . import material_slots, native


def millimetres_per_unit(scene):
    """Blender units are metres times the unit scale (1 when there is no unit system)."""
    units = scene.unit_settings
    return 1000.0 * (units.scale_length if units.system != "NONE" else 1.0)


def corner_uvs(mesh, layer, loops):
    """The UVs of `layer` at the corners `loops`, n × 2."""
    uvs = np.empty(2 * len(mesh.loops), dtype=np.float32)
    layer.data.foreach_get("uv", uvs)
    return uvs.reshape(-1, 2)[loops]


def mesh_arrays(obj, depsgraph, uv_map, texture_uv_keys=()):
    """One vertex per triangle corner: positions, normals (world space) and the UVs of
    `uv_map` ("" for the active one; None when the mesh has none), the triangles' indices and
    material slots, and one UV set per (UV map, Mapping transform) of `texture_uv_keys`."""
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        count = len(mesh.loop_triangles)
        loops = np.empty(3 * count, dtype=np.int32)
        vertices = np.empty(3 * count, dtype=np.int32)
        mesh.loop_triangles.foreach_get("loops", loops)
        mesh.loop_triangles.foreach_get("vertices", vertices)
        slots = np.empty(count, dtype=np.int32)
        mesh.loop_triangles.foreach_get("material_index", slots)
        co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
        mesh.vertices.foreach_get("co", co)
        normals = np.empty(3 * len(mesh.loops), dtype=np.float32)
        mesh.corner_normals.foreach_get("vector", normals)
        layer = mesh.uv_layers.get(uv_map) if uv_map else mesh.uv_layers.active
        uvs = None if layer is None else corner_uvs(mesh, layer, loops).reshape(-1)
        texture_uvs = []
        for name, transform in texture_uv_keys:
            render = next((uv for uv in mesh.uv_layers if uv.active_render), None)
            source = mesh.uv_layers.get(name) if name else render
            corners = corner_uvs(mesh, source, loops) if source is not None else np.zeros((3 * count, 2))
            texture_uvs.append(
                np.ascontiguousarray(
                    material_slots.apply_transform(corners, transform), dtype=np.float32
                ).reshape(-1)
            )
    finally:
        evaluated.to_mesh_clear()
    world = np.array(obj.matrix_world, dtype=np.float64)
    linear, offset = world[:3, :3], world[:3, 3]
    positions = co.reshape(-1, 3)[vertices] @ linear.T + offset
    normal_matrix = np.linalg.inv(linear).T if abs(np.linalg.det(linear)) > 1e-30 else linear
    corner_normals = normals.reshape(-1, 3)[loops] @ normal_matrix.T
    corner_normals /= np.maximum(np.linalg.norm(corner_normals, axis=1, keepdims=True), 1e-30)
    indices = np.arange(3 * count, dtype=np.uint32).reshape(-1, 3)
    if np.linalg.det(linear) < 0:
        indices = indices[:, [0, 2, 1]]
    return (
        np.ascontiguousarray(positions, dtype=np.float32).reshape(-1),
        np.ascontiguousarray(corner_normals, dtype=np.float32).reshape(-1),
        None if uvs is None else np.ascontiguousarray(uvs, dtype=np.float32),
        np.ascontiguousarray(indices, dtype=np.uint32).reshape(-1),
        slots,
        texture_uvs,
    )


def light_struct(obj):
    """The native light for a Blender light object, or None for kinds not baked and for lights
    that do not reach diffuse (and so subsurface) rays in Cycles."""
    data = obj.data
    if not obj.visible_diffuse or data.diffuse_factor <= 0.0:
        return None
    world = obj.matrix_world
    linear = world.to_3x3()
    scale = (linear.col[0].length + linear.col[1].length) / 2
    light = native.Light()
    light.colour = native.Vec3(*data.color)
    light.power = data.energy
    light.exposure = data.exposure
    light.temperature_colour = native.Vec3(
        *(data.temperature_color if data.use_temperature else (1.0, 1.0, 1.0))
    )
    light.diffuse_factor = data.diffuse_factor
    light.normalize = int(data.normalize)
    light.casts_shadow = int(data.use_shadow)
    light.position = native.Vec3(*world.translation)
    light.direction = native.Vec3(*(linear @ _axis(0, 0, -1)).normalized())
    light.tangent = native.Vec3(*(linear @ _axis(1, 0, 0)).normalized())
    if data.type == "SUN":
        light.kind = native.LIGHT_SUN
        light.angle = data.angle
    elif data.type in ("POINT", "SPOT"):
        light.kind = native.LIGHT_POINT if data.type == "POINT" else native.LIGHT_SPOT
        light.size = data.shadow_soft_size
        if data.type == "SPOT":
            light.spot_size = data.spot_size
            light.spot_blend = data.spot_blend
    elif data.type == "AREA":
        light.spread = data.spread
        if data.shape in ("DISK", "ELLIPSE"):
            light.kind = native.LIGHT_DISK
            light.size = data.size * scale
        else:
            light.kind = native.LIGHT_RECTANGLE
            light.size = data.size * linear.col[0].length
            square = data.shape == "SQUARE"
            light.size_y = (data.size if square else data.size_y) * linear.col[1].length
    else:
        return None
    return light


def _axis(x, y, z):
    from mathutils import Vector

    return Vector((x, y, z))


def world_colour(scene):
    """The world's background colour and strength (black when it has none)."""
    world = scene.world
    if world is None:
        return (0.0, 0.0, 0.0), 0.0
    if world.use_nodes and world.node_tree:
        for node in world.node_tree.nodes:
            if node.type == "BACKGROUND" and node.outputs[0].is_linked:
                colour, strength = node.inputs["Color"], node.inputs["Strength"]
                if colour.is_linked:
                    return (0.0, 0.0, 0.0), 0.0
                return tuple(colour.default_value[:3]), float(strength.default_value)
        return (0.0, 0.0, 0.0), 0.0
    return tuple(world.color), 1.0


def material_struct(settings, obj, keep):
    """The native materials the panel asks for, for `obj`: a list of one for a preset or a
    layers file, else one per distinct material of its slots (the order of
    material_slots.object_slots, which the mesh's material indices follow). `keep` holds the
    strings and pixels alive."""
    source = settings.material_source
    if source == "PRESET":
        material = native.Material()
        material.kind = native.MATERIAL_PRESET
        keep.append(settings.preset.encode("utf-8"))
        material.name = keep[-1]
        return [material]
    if source == "LAYERS":
        path = bpy.path.abspath(settings.layers_file)
        try:
            with open(path, encoding="utf-8") as file:
                text = file.read()
        except OSError as error:
            raise native.NativeError(2, f"{path}: cannot read the layers file: {error}") from error
        material = native.Material()
        material.kind = native.MATERIAL_TOML
        keep += [text.encode("utf-8"), path.encode("utf-8")]
        material.toml, material.name = keep[-2], keep[-1]
        return [material]
    slots, _ = material_slots.object_slots(obj)
    if all(slot.left_out for slot in slots):
        reasons = "; ".join(slot.left_out for slot in slots)
        raise native.NativeError(
            2, f"object `{obj.name}`: no material slot has subsurface to bake ({reasons})"
        )
    uv_keys = material_slots.texture_uv_keys(slots)
    return [principled_struct(settings, slot, uv_keys, keep) for slot in slots]


def principled_struct(settings, slot, uv_keys, keep):
    """The native material of one slot: its Principled inputs and Base Color image, or
    MATERIAL_NONE for a slot without subsurface (its faces are left out)."""
    material = native.Material()
    name = slot.material.name if slot.material is not None else "(empty slot)"
    keep.append(name.encode("utf-8"))
    material.name = keep[-1]
    if slot.left_out:
        material.kind = native.MATERIAL_NONE
        return material
    inputs = slot.principled.inputs
    material.kind = native.MATERIAL_PRINCIPLED
    material.base_colour = native.Vec3(*inputs["Base Color"].default_value[:3])
    material.subsurface_weight = inputs["Subsurface Weight"].default_value
    material.radius = native.Vec3(*inputs["Subsurface Radius"].default_value)
    material.scale = inputs["Subsurface Scale"].default_value
    material.subsurface_method = native.SUBSURFACE_METHODS.get(slot.principled.subsurface_method, 1)
    material.ior = value_of(inputs, "IOR", 1.5)
    material.specular_ior_level = value_of(inputs, "Specular IOR Level", 0.5)
    material.subsurface_ior = value_of(inputs, "Subsurface IOR", 1.4)
    material.anisotropy = value_of(inputs, "Subsurface Anisotropy", 0.0)
    # Roughness is Cycles' GGX specular layer over the subsurface, not the rough boundary of
    # Donner & Jensen that `roughness` describes, and the glTF and USD readers leave it out
    # too: a smooth boundary keeps the three doors one bake (README, "Materials").
    material.roughness = 0.0
    material.albedo_mapping = (
        native.ALBEDO_PHYSICAL if settings.albedo_mapping == "PHYSICAL" else native.ALBEDO_CYCLES
    )
    if slot.texture is not None:
        node = slot.texture.node
        image = node.image
        pixels = material_slots.linear_pixels(slot.texture)
        keep += [pixels, image.name.encode("utf-8")]
        material.image_pixels = native.floats(pixels)
        material.image_name = keep[-1]
        material.image_width, material.image_height = image.size
        material.image_channels = image.channels
        material.image_uv_set = 1 + uv_keys.index(slot.texture.uv_key)
        material.image_extension = native.EXTENSIONS.get(node.extension, 0)
        material.image_nearest = int(node.interpolation == "Closest")
    return material


def material_notes(settings, obj):
    """What the bake does not read of the object's materials, one line each: slots left out
    (no subsurface), nodes on Base Color it does not follow, textures on other inputs."""
    if settings.material_source in ("PRESET", "LAYERS"):
        return []
    slots, _ = material_slots.object_slots(obj)
    notes = []
    for slot in slots:
        if slot.left_out and not all(s.left_out for s in slots):
            notes.append(f"{obj.name}: {slot.left_out}; its faces are left out of the bake (texels empty)")
        notes += [f"{obj.name}: {note}" for note in slot.notes]
    return notes


def value_of(inputs, name, default):
    """An input's value, or `default` where the node has no such input."""
    socket = inputs.get(name)
    return socket.default_value if socket is not None else default


def rendered_collections(view_layer):
    """The collections whose objects render in `view_layer`: neither excluded from it nor hidden
    from renders, nor inside one that is."""
    rendered = set()

    def walk(layer_collection):
        if layer_collection.exclude or layer_collection.collection.hide_render:
            return
        rendered.add(layer_collection.collection.name)
        for child in layer_collection.children:
            walk(child)

    walk(view_layer.layer_collection)
    return rendered


def renders(obj, collections):
    """True when Cycles renders `obj`: not hidden from renders and in a rendered collection
    (what the viewport shows does not matter)."""
    if obj.hide_render:
        return False
    return any(c.name in collections for c in obj.users_collection)


def build_scene(context, uv_map):
    """A native scene of every mesh that renders (the shadow casters) and light, and the world."""
    scene = context.scene
    depsgraph = context.evaluated_depsgraph_get()
    collections = rendered_collections(context.view_layer)
    native_scene = native.Scene(millimetres_per_unit(scene))
    try:
        for obj in scene.objects:
            if not renders(obj, collections):
                continue
            if obj.type == "MESH":
                slots, index_of = material_slots.object_slots(obj)
                keys = material_slots.texture_uv_keys(slots)
                *arrays, slot_of_face, texture_uvs = mesh_arrays(obj, depsgraph, uv_map, keys)
                if len(arrays[3]):
                    faces = np.asarray(index_of, dtype=np.uint32)[np.clip(slot_of_face, 0, len(index_of) - 1)]
                    native_scene.add_mesh(obj.name, *arrays, faces, texture_uvs)
            elif obj.type == "LIGHT":
                light = light_struct(obj)
                if light is not None:
                    native_scene.add_light(light)
        colour, strength = world_colour(scene)
        native_scene.set_world(colour, strength if math.isfinite(strength) else 0.0)
    except Exception:
        native_scene.close()
        raise
    return native_scene
