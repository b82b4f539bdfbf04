"""What an artist would notice changed in a Blender scene, as plain comparable data:
modes, selection, UV maps (names, active, render, coordinates), mesh selection, images
(source, path, size, packed bytes, pixels, colour space, users), materials' nodes and
links and the objects' material slots, and the files of a folder."""

import hashlib
import pathlib

import numpy as np


def _digest(values):
    return hashlib.sha256(np.ascontiguousarray(values).tobytes()).hexdigest()


def _floats(collection, attribute, width):
    values = np.empty(width * len(collection), dtype=np.float32)
    collection.foreach_get(attribute, values)
    return _digest(values)


def _flags(collection, attribute):
    values = np.empty(len(collection), dtype=bool)
    collection.foreach_get(attribute, values)
    return _digest(values)


def _image(image):
    pixels = None
    if image.has_data or image.source in ("GENERATED", "FILE"):
        values = np.empty(len(image.pixels), dtype=np.float32)
        image.pixels.foreach_get(values)
        pixels = _digest(values)
    return {
        "source": image.source,
        "filepath": image.filepath,
        "size": tuple(image.size),
        "packed": _digest(np.frombuffer(image.packed_file.data, np.uint8)) if image.packed_file else None,
        "pixels": pixels,
        "colour space": image.colorspace_settings.name,
        "fake user": image.use_fake_user,
        "users": image.users,
    }


def _material(material):
    if material.node_tree is None:
        return None
    nodes = {
        node.name: (
            node.bl_idname,
            getattr(node, "image", None) and node.image.name,
            getattr(node, "uv_map", None),
            getattr(node, "is_active_output", None),
        )
        for node in material.node_tree.nodes
    }
    links = sorted(
        (link.from_node.name, link.from_socket.identifier, link.to_node.name, link.to_socket.identifier)
        for link in material.node_tree.links
    )
    return {"nodes": nodes, "links": links}


def snapshot(folder=None):
    """The scene as comparable data; with `folder`, its files' names and contents too."""
    import bpy

    view_layer = bpy.context.view_layer
    state = {
        "objects": {
            o.name: {
                "mode": o.mode,
                "selected": o.select_get(),
                "slots": [(slot.link, slot.material and slot.material.name) for slot in o.material_slots],
            }
            for o in bpy.data.objects
        },
        "active": view_layer.objects.active and view_layer.objects.active.name,
        "meshes": {
            m.name: {
                "uv maps": [
                    (layer.name, layer.active, layer.active_render, _floats(layer.data, "uv", 2))
                    for layer in m.uv_layers
                ],
                "selection": [
                    _flags(getattr(m, items), flag)
                    for items in ("vertices", "edges", "polygons")
                    for flag in ("select", "hide")
                ],
            }
            for m in bpy.data.meshes
        },
        "images": {image.name: _image(image) for image in bpy.data.images},
        "materials": {m.name: _material(m) for m in bpy.data.materials},
    }
    if folder is not None:
        root = pathlib.Path(folder)
        state["files"] = (
            {
                str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
                for p in sorted(root.rglob("*"))
                if p.is_file()
            }
            if root.exists()
            else None
        )
    return state
