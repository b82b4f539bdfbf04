"""Blender's materials read as Cycles renders them, slot by slot: the Principled BSDF that
feeds each material's active Material Output, and the Image Texture its Base Color reads
(with the UV map and Mapping node its Vector input follows). What the add-on cannot pass on
is said in notes; nothing here changes the artist's data."""

import dataclasses

import numpy as np

from . import colour_nodes
from .wiring import NODES

# The Material Output that Show in Material adds and makes active.
SHOWN_OUTPUT = NODES["output"][1]
# Nodes a value passes through unchanged.
PASS_THROUGH = {"REROUTE"}
# Principled inputs whose node links the bake does not follow (each read at its own value).
UNREAD_LINKS = (
    "Subsurface Weight",
    "Subsurface Radius",
    "Subsurface Scale",
    "Subsurface IOR",
    "Subsurface Anisotropy",
    "IOR",
    "Specular IOR Level",
)


@dataclasses.dataclass
class Texture:
    """An Image Texture on Base Color: its image, the UV map its coordinates come from ("" is
    the active render UV map), the affine map a Mapping node applies to them, and the colour
    nodes between the image and Base Color (Mix, Bright/Contrast, Gamma, Invert)."""

    node: object
    uv_map: str
    transform: tuple | None = None
    # Texel-by-texel changes of the colour between the image and Base Color, image first.
    colour_steps: tuple = ()

    @property
    def uv_key(self):
        """What makes its coordinates: one texture UV set per distinct key."""
        return (self.uv_map, self.transform)


@dataclasses.dataclass
class Slot:
    """One distinct material of an object: the material (None for an empty slot), the
    Principled BSDF that feeds its active output, the Base Color texture, and why any of them
    is not read (`left_out` says why the slot has no subsurface to bake)."""

    material: object
    principled: object = None
    texture: Texture | None = None
    left_out: str | None = None
    notes: list = dataclasses.field(default_factory=list)


def upstream(socket):
    """The node and output socket that feed `socket` through reroutes, or (None, None) when it
    is not linked (a muted or invalid link counts as none, as in Cycles)."""
    seen = 0
    while socket is not None and socket.is_linked and seen < 64:
        link = socket.links[0]
        if link.is_muted or not link.is_valid:
            return None, None
        node = link.from_node
        if node.type not in PASS_THROUGH:
            return node, link.from_socket
        socket = node.inputs[0] if node.inputs else None
        seen += 1
    return None, None


def principled_of(material):
    """The Principled BSDF that feeds the material's active Cycles output, and a note when it
    is reached through a mix or there is none."""
    tree = material.node_tree
    output = tree.get_output_node("CYCLES") if tree is not None else None
    if output is not None and output.name == SHOWN_OUTPUT:
        # Show in Material made its own output active; the material is the artist's.
        artist = [
            node
            for node in tree.nodes
            if node.type == "OUTPUT_MATERIAL"
            and node.name != SHOWN_OUTPUT
            and node.target in ("ALL", "CYCLES")
        ]
        output = artist[0] if artist else None
    if output is None:
        return None, "it has no active Material Output"
    node, _ = upstream(output.inputs["Surface"])
    if node is None:
        return None, "nothing feeds its active Material Output's Surface"
    if node.type == "BSDF_PRINCIPLED":
        return node, None
    found = []

    def collect(shader_node, depth):
        if shader_node.type == "BSDF_PRINCIPLED":
            found.append(shader_node)
        elif shader_node.type in ("MIX_SHADER", "ADD_SHADER") and depth < 8:
            for socket in shader_node.inputs:
                if socket.type == "SHADER":
                    child, _ = upstream(socket)
                    if child is not None:
                        collect(child, depth + 1)

    collect(node, 0)
    if len(found) == 1:
        return found[0], (
            f"the Principled BSDF `{found[0].name}` inside `{node.name}` is baked alone; "
            f"the {node.bl_label} is not applied"
        )
    what = f"{len(found)} Principled BSDFs" if found else "no Principled BSDF"
    return None, f"its active output is fed by `{node.name}` ({node.bl_label}) with {what} to read"


def uv_source(texture_node, mesh):
    """(uv_map, transform) the Image Texture's Vector input reads, or a note saying why not."""
    node, socket = upstream(texture_node.inputs["Vector"])
    transform = None
    if node is not None and node.type == "MAPPING" and node.mute:
        # A muted Mapping passes its Vector through.
        node, socket = upstream(node.inputs["Vector"])
    elif node is not None and node.type == "MAPPING":
        transform = mapping_transform(node)
        if transform is None:
            return None, f"its Vector comes through Mapping `{node.name}` with linked inputs or Normal type"
        node, socket = upstream(node.inputs["Vector"])
        if node is None:
            return None, f"Mapping `{texture_node.name}` reads no texture coordinates"
    if node is None:
        uv_map = ""
    elif node.type == "UVMAP":
        uv_map = node.uv_map
    elif node.type == "TEX_COORD" and socket.name == "UV":
        uv_map = ""
    else:
        return None, f"its Vector comes from `{node.name}` ({node.bl_label}), not from a UV map"
    if uv_map and mesh.uv_layers.get(uv_map) is None:
        return None, f"it reads UV map `{uv_map}`, which the mesh does not have"
    if not uv_map and not any(layer.active_render for layer in mesh.uv_layers):
        return None, "it reads the active render UV map, and the mesh has none"
    return (uv_map, transform), None


def mapping_transform(node):
    """The Mapping node's map of (u, v, 0) as a flat 3 × 4 affine matrix (rows), or None when
    an input is linked or the node maps normals."""
    from mathutils import Euler, Matrix

    inputs = node.inputs
    if any(inputs[name].is_linked for name in ("Location", "Rotation", "Scale") if name in inputs):
        return None
    location = inputs["Location"].default_value if "Location" in inputs else (0.0, 0.0, 0.0)
    rotation = Euler(inputs["Rotation"].default_value, "XYZ").to_matrix()
    scale = Matrix.Diagonal(inputs["Scale"].default_value)
    kind = node.vector_type
    if kind == "POINT":
        linear, offset = rotation @ scale, np.array(location)
    elif kind == "VECTOR":
        linear, offset = rotation @ scale, np.zeros(3)
    elif kind == "TEXTURE":
        if any(abs(s) < 1e-12 for s in inputs["Scale"].default_value):
            return None
        linear = scale.inverted() @ rotation.transposed()
        offset = -np.array(linear) @ np.array(location)
    else:
        return None
    matrix = np.hstack([np.array(linear), np.asarray(offset).reshape(3, 1)])
    return tuple(round(float(v), 9) for v in matrix.reshape(-1))


def apply_transform(uvs, transform):
    """`uvs` (n × 2) mapped by a flat 3 × 4 affine `transform`, keeping x and y."""
    if transform is None:
        return uvs
    matrix = np.array(transform).reshape(3, 4)
    points = np.column_stack([uvs, np.zeros(len(uvs))])
    return (points @ matrix[:, :3].T + matrix[:, 3])[:, :2]


def base_colour_texture(material, principled, mesh):
    """The Image Texture whose Color feeds Base Color, and a note when a node feeds it that the
    add-on does not read (the socket's own colour is baked then)."""
    socket = principled.inputs["Base Color"]
    node, output = upstream(socket)
    if node is None:
        return None, None
    colour = ", ".join(f"{c:.3f}" for c in socket.default_value[:3])
    steps = []
    while (step := colour_nodes.colour_step(node)) is not None:
        onward, function = step
        steps.insert(0, function)
        node, output = upstream(onward)
        if node is None:
            return None, None
    unread = (
        f"material `{material.name}`: Base Color is driven by `{node.name}` ({node.bl_label})"
        f"{{}}; it is baked as the socket's colour ({colour})"
    )
    if node.type != "TEX_IMAGE" or output.name != "Color":
        return None, unread.format(", which the add-on does not read")
    if node.mute:
        return None, unread.format(", which is muted")
    image = node.image
    if image is None:
        return None, unread.format(", which has no image")
    if node.projection != "FLAT":
        return None, unread.format(f" with {node.projection.lower()} projection")
    if image.source not in ("FILE", "GENERATED") or image.size[0] * image.size[1] == 0:
        return None, unread.format(f", whose image `{image.name}` has no pixels (a missing file?)")
    if image.channels not in (3, 4):
        return None, unread.format(f", whose image `{image.name}` has {image.channels} channels")
    source, why = uv_source(node, mesh)
    if source is None:
        return None, unread.format(f": {why}")
    return Texture(node, *source, colour_steps=tuple(steps)), None


def colour_space_note(material, image):
    """A note when the image's colour space is neither sRGB nor linear (read as linear)."""
    space = image.colorspace_settings.name
    if image.is_float or space == "sRGB" or space in ("Non-Color", "Raw") or space.startswith("Linear"):
        return None
    return f"material `{material.name}`: image `{image.name}` is in colour space {space}, read as linear"


def read_slot(material, mesh):
    """What the bake reads of one material."""
    if material is None:
        return Slot(None, left_out="an empty material slot")
    principled, note = principled_of(material)
    slot = Slot(material, principled)
    if principled is None:
        slot.left_out = f"material `{material.name}`: {note}"
        return slot
    if note:
        slot.notes.append(f"material `{material.name}`: {note}")
    weight = principled.inputs["Subsurface Weight"].default_value
    if not weight > 0.0:
        slot.left_out = f"material `{material.name}`: Subsurface Weight is {weight:g}"
    for name in UNREAD_LINKS:
        socket = principled.inputs.get(name)
        node, _ = upstream(socket) if socket is not None else (None, None)
        if node is not None:
            slot.notes.append(
                f"material `{material.name}`: {name} is driven by `{node.name}` ({node.bl_label}), "
                f"which is not applied; it is baked at the socket's value"
            )
    slot.texture, note = base_colour_texture(material, principled, mesh)
    if note:
        slot.notes.append(note)
    if slot.texture is not None and (note := colour_space_note(material, slot.texture.node.image)):
        slot.notes.append(note)
    return slot


def object_slots(obj):
    """The object's distinct materials in slot order, and per slot the index of its
    material among them (an object without slots has one empty one)."""
    materials = [slot.material for slot in obj.material_slots] or [None]
    distinct, index_of = [], []
    for material in materials:
        if material not in distinct:
            distinct.append(material)
        index_of.append(distinct.index(material))
    return [read_slot(m, obj.data) for m in distinct], index_of


def texture_uv_keys(slots):
    """The distinct coordinate sources the slots' textures read, in slot order: the mesh's
    texture UV sets 1, 2, ... (set 0 is the one baked into)."""
    keys = []
    for slot in slots:
        if slot.texture is not None and slot.left_out is None and slot.texture.uv_key not in keys:
            keys.append(slot.texture.uv_key)
    return keys


def linear_pixels(texture):
    """The texture's image as linear float32 texels, rows from the bottom (Blender's order),
    changed by its colour steps: byte images in sRGB decoded by the sRGB transfer; float
    images are linear already. The steps apply to texels where Cycles applies them to the
    filtered colour: the same under Closest filtering, and under bilinear filtering for the
    affine steps (Mix, Invert; Bright/Contrast where it does not clip); Gamma's curve then
    differs between texel centres."""
    image = texture.node.image
    pixels = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(pixels)
    texels = pixels.reshape(-1, image.channels)
    if not image.is_float and image.colorspace_settings.name == "sRGB":
        rgb = texels[:, :3]
        texels[:, :3] = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    for step in texture.colour_steps:
        texels[:, :3] = step(texels[:, :3].astype(np.float64))
    return np.ascontiguousarray(pixels)
