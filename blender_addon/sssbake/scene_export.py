"""The Blender scene as the library takes it: evaluated meshes (modifiers applied) as flat
world-space arrays with each triangle's material and the UV sets their textures read, lights
and the world colour in Blender's own units, and materials slot by slot. Only data moves
here; every conversion of units and physics happens in the library."""

import math

import bpy
import numpy as np

from . import binding, material_slots


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


def light_fields(obj):
    """The library's light for a Blender light object (`sssbake.Scene.add_light`'s
    fields), or None for kinds not baked and for lights that do not reach diffuse (and so
    subsurface) rays in Cycles."""
    data = obj.data
    if not obj.visible_diffuse or data.diffuse_factor <= 0.0:
        return None
    world = obj.matrix_world
    linear = world.to_3x3()
    scale = (linear.col[0].length + linear.col[1].length) / 2
    light = {
        "colour": tuple(data.color),
        "power": data.energy,
        "exposure": data.exposure,
        "temperature_colour": tuple(data.temperature_color if data.use_temperature else (1.0, 1.0, 1.0)),
        "diffuse_factor": data.diffuse_factor,
        "normalize": bool(data.normalize),
        "casts_shadow": bool(data.use_shadow),
        "position": tuple(world.translation),
        "direction": tuple((linear @ _axis(0, 0, -1)).normalized()),
        "tangent": tuple((linear @ _axis(1, 0, 0)).normalized()),
    }
    if data.type == "SUN":
        light.update(kind="sun", angle=data.angle)
    elif data.type in ("POINT", "SPOT"):
        light.update(kind=data.type.lower(), size=data.shadow_soft_size)
        if data.type == "SPOT":
            light.update(spot_size=data.spot_size, spot_blend=data.spot_blend)
    elif data.type == "AREA":
        light["spread"] = data.spread
        if data.shape in ("DISK", "ELLIPSE"):
            light.update(kind="disk", size=data.size * scale)
        else:
            square = data.shape == "SQUARE"
            light.update(
                kind="rectangle",
                size=data.size * linear.col[0].length,
                size_y=(data.size if square else data.size_y) * linear.col[1].length,
            )
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


def materials_of(settings, obj):
    """The materials the panel asks for, for `obj` (`sssbake.Scene.bake_object`'s): a list
    of one for a preset or a layers file, else one per distinct material of its slots (the
    order of material_slots.object_slots, which the mesh's material indices follow)."""
    source = settings.material_source
    if source == "PRESET":
        return [{"kind": "preset", "name": settings.preset}]
    if source == "LAYERS":
        path = bpy.path.abspath(settings.layers_file)
        try:
            with open(path, encoding="utf-8") as file:
                text = file.read()
        except OSError as error:
            raise binding.InputError(f"{path}: cannot read the layers file: {error}", file=path) from error
        return [{"kind": "toml", "toml": text, "name": path}]
    slots, _ = material_slots.object_slots(obj)
    if all(slot.left_out for slot in slots):
        reasons = "; ".join(slot.left_out for slot in slots)
        raise binding.InputError(
            f"object `{obj.name}`: no material slot has subsurface to bake ({reasons})", object=obj.name
        )
    uv_keys = material_slots.texture_uv_keys(slots)
    return [principled_material(settings, slot, uv_keys) for slot in slots]


def principled_material(settings, slot, uv_keys):
    """The material of one slot: its Principled inputs and Base Color image, or `none` for a
    slot without subsurface (its faces are left out)."""
    name = slot.material.name if slot.material is not None else "(empty slot)"
    if slot.left_out:
        return {"kind": "none", "name": name}
    inputs = slot.principled.inputs
    material = {
        "kind": "principled",
        "name": name,
        "base_colour": tuple(inputs["Base Color"].default_value[:3]),
        "subsurface_weight": inputs["Subsurface Weight"].default_value,
        "radius": tuple(inputs["Subsurface Radius"].default_value),
        "scale": inputs["Subsurface Scale"].default_value,
        "method": slot.principled.subsurface_method,
        "ior": value_of(inputs, "IOR", 1.5),
        "specular_ior_level": value_of(inputs, "Specular IOR Level", 0.5),
        "subsurface_ior": value_of(inputs, "Subsurface IOR", 1.4),
        "anisotropy": value_of(inputs, "Subsurface Anisotropy", 0.0),
        # Roughness is Cycles' GGX specular layer over the subsurface, not the rough boundary
        # of Donner & Jensen that `roughness` describes, and the glTF and USD readers leave it
        # out too: a smooth boundary keeps the three doors one bake (docs/materials.md, "Materials").
        "roughness": 0.0,
        "albedo": "physical" if settings.albedo_mapping == "PHYSICAL" else "cycles",
    }
    if slot.texture is not None:
        node = slot.texture.node
        image = node.image
        width, height = image.size
        material["image"] = {
            "pixels": material_slots.linear_pixels(slot.texture),
            "width": width,
            "height": height,
            "channels": image.channels,
            "uv_set": 1 + uv_keys.index(slot.texture.uv_key),
            "extension": node.extension,
            "nearest": node.interpolation == "Closest",
            "name": image.name,
        }
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
    """The library's scene of every mesh that renders (the shadow casters) and light, and
    the world."""
    scene = context.scene
    depsgraph = context.evaluated_depsgraph_get()
    collections = rendered_collections(context.view_layer)
    built = binding.package().Scene(millimetres_per_unit(scene))
    for obj in scene.objects:
        if not renders(obj, collections):
            continue
        if obj.type == "MESH":
            slots, index_of = material_slots.object_slots(obj)
            keys = material_slots.texture_uv_keys(slots)
            positions, normals, uvs, indices, slot_of_face, texture_uvs = mesh_arrays(
                obj, depsgraph, uv_map, keys
            )
            if len(indices):
                faces = np.asarray(index_of, dtype=np.uint32)[np.clip(slot_of_face, 0, len(index_of) - 1)]
                built.add_mesh(
                    obj.name,
                    positions,
                    indices,
                    normals=normals,
                    uvs=uvs,
                    material_indices=faces,
                    texture_uvs=texture_uvs,
                )
        elif obj.type == "LIGHT":
            light = light_fields(obj)
            if light is not None:
                built.add_light(**light)
    colour, strength = world_colour(scene)
    built.set_world(colour, strength if math.isfinite(strength) else 0.0)
    return built
