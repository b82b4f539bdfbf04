"""Show in Material: the diffuse map through Image Texture → Emission → a new active
Material Output in each material of the object; the artist's nodes stay, their output
inactive. A material another object also uses is left alone (it would show this bake on
that object too) unless per-object copies are asked for; either way the artist is told."""

import bpy

NODES = {
    "uv": ("ShaderNodeUVMap", "sssbake UV", (-900, -600)),
    "texture": ("ShaderNodeTexImage", "sssbake diffuse", (-700, -600)),
    "emission": ("ShaderNodeEmission", "sssbake emission", (-400, -600)),
    "output": ("ShaderNodeOutputMaterial", "sssbake output", (-200, -600)),
}


def other_users(material, obj):
    """The names of the objects other than `obj` whose slots hold `material`."""
    return sorted(
        o.name
        for o in bpy.data.objects
        if o != obj and any(slot.material == material for slot in getattr(o, "material_slots", ()))
    )


def show_in_material(obj, image, uv_map, copy_shared, changes):
    """Wires `image` into every material of `obj`; returns what the artist should know
    (materials left alone, copies made), each a sentence. Changes go into `changes`."""
    notes = []
    if not any(slot.material for slot in obj.material_slots):
        return [f"{obj.name}: has no material to show the bake in"]
    for index, slot in enumerate(obj.material_slots):
        material = slot.material
        if material is None:
            continue
        sharing = other_users(material, obj)
        if sharing:
            if not copy_shared:
                notes.append(
                    f"{obj.name}: material `{material.name}` is shared with {_names(sharing)}, so it "
                    "was left as it is (tick Copy Shared Materials to show each object's bake in its "
                    "own copy)"
                )
                continue
            original, material = material, _own_copy(obj, index, material, changes)
            notes.append(
                f"{obj.name}: shows its bake in `{material.name}`, its own copy of `{original.name}` "
                f"(which {_names(sharing)} keep)"
            )
        if material.node_tree is None:
            notes.append(f"{obj.name}: material `{material.name}` has no nodes to show the bake in")
            continue
        _wire(material.node_tree, image, uv_map, changes)
    return notes


def _names(names):
    return ", ".join(f"`{n}`" for n in names)


def _own_copy(obj, index, material, changes):
    """A copy of `material` in slot `index` of `obj` alone (the slot linked to the object,
    so other users of the mesh keep the original)."""
    slot = obj.material_slots[index]
    link = slot.link
    copy = material.copy()
    copy.name = f"{material.name} ({obj.name})"

    def undo():
        slot.link = "OBJECT"
        slot.material = None
        slot.link = link
        if link == "OBJECT":
            slot.material = material
        bpy.data.materials.remove(copy)

    changes.record(undo)
    slot.link = "OBJECT"
    slot.material = copy
    return slot.material


def _wire(tree, image, uv_map, changes):
    nodes = tree.nodes
    made = {}
    for key, (kind, name, location) in NODES.items():
        node = nodes.get(name)
        if node is None:
            node = nodes.new(kind)
            node.name = node.label = name
            node.location = location
            changes.record(lambda name=name: nodes.remove(nodes[name]))
        made[key] = node
    texture, uv = made["texture"], made["uv"]
    previous_image, previous_map = texture.image, uv.uv_map
    changes.record(lambda: _set(nodes, previous_image, previous_map))
    uv.uv_map = uv_map
    texture.image = image
    for source, target in (
        (uv.outputs["UV"], texture.inputs["Vector"]),
        (texture.outputs["Color"], made["emission"].inputs["Color"]),
        (made["emission"].outputs["Emission"], made["output"].inputs["Surface"]),
    ):
        _link(tree, source, target, changes)
    outputs = [n for n in nodes if n.type == "OUTPUT_MATERIAL"]
    active = {n.name: n.is_active_output for n in outputs}
    changes.record(lambda: _activate(nodes, active))
    for node in outputs:
        node.is_active_output = node == made["output"]


def _set(nodes, image, uv_map):
    nodes[NODES["texture"][1]].image = image
    nodes[NODES["uv"][1]].uv_map = uv_map


def _link(tree, source, target, changes):
    """Links `source` into `target`, recording the link it replaces."""
    before = [(link.from_node.name, link.from_socket.identifier) for link in target.links]
    node, socket = target.node.name, target.identifier

    def undo():
        # The sockets are found again by name: the node objects may have been re-made.
        nodes = tree.nodes
        if node not in nodes:
            return
        target = next(s for s in nodes[node].inputs if s.identifier == socket)
        for link in list(target.links):
            tree.links.remove(link)
        for from_node, from_socket in before:
            if from_node in nodes:
                output = next(s for s in nodes[from_node].outputs if s.identifier == from_socket)
                tree.links.new(output, target)

    changes.record(undo)
    tree.links.new(source, target)


def _activate(nodes, active):
    for name, is_active in active.items():
        if name in nodes:
            nodes[name].is_active_output = is_active
