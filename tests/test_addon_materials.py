"""The add-on reads materials as Blender means them: every material slot bakes its own
faces, the Principled BSDF read is the one feeding the active Material Output, an Image
Texture on Base Color is baked through the UV map (and Mapping node) its Vector reads with
its colour space decoded, a slot without subsurface is left out with a warning, and inputs
the bake does not follow are reported.

Each is compared with an independent bake of the same plane where one exists: one material
on every face, a plain Base Color equal to a one-colour texture's decoded colour."""

import numpy as np
import pytest
from conftest import srgb_to_linear
from test_blender_addon import pixels

MM = 0.001
RESOLUTION = 32
PALE, DARK = (0.8, 0.6, 0.5), (0.3, 0.15, 0.1)


def skin(name, colour, radius=(1.0, 0.5, 0.25)):
    """A Random Walk Principled material of `colour` (2 mm scale)."""
    import bpy

    material = bpy.data.materials.new(name)
    if material.node_tree is None:
        material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*colour, 1.0)
    bsdf.inputs["Subsurface Weight"].default_value = 1.0
    bsdf.inputs["Subsurface Radius"].default_value = radius
    bsdf.inputs["Subsurface Scale"].default_value = 2 * MM
    bsdf.subsurface_method = "RANDOM_WALK"
    return material


def plane_scene(materials, right_slot=1):
    """A 40 mm plane of 8 × 8 faces under a sun, its slots `materials`; faces with x > 0
    use slot `right_slot`, the others slot 0. The plane is selected."""
    import bpy

    bpy.ops.mesh.primitive_grid_add(x_subdivisions=8, y_subdivisions=8, size=40 * MM)
    plane = bpy.context.active_object
    plane.name = "Plane"
    for material in materials:
        plane.data.materials.append(material)
    for polygon in plane.data.polygons:
        polygon.material_index = right_slot if polygon.center.x > 0 else 0
    bpy.ops.object.light_add(type="SUN", rotation=(0.2, 0.1, 0.0))
    bpy.context.active_object.data.energy = 1.0
    bpy.ops.object.select_all(action="DESELECT")
    plane.select_set(True)
    bpy.context.view_layer.objects.active = plane
    return plane


def bake():
    """Bakes the selection's subsurface map; returns its RGBA pixels (rows from v = 0)."""
    import bpy

    result = bpy.ops.sssbake.bake(resolution=RESOLUTION, method="BRUTE", outputs={"SUBSURFACE"})
    assert result == {"FINISHED"}
    return pixels("Plane_subsurface").copy()


def halves(image):
    """The texels left and right of the middle columns (which may belong to either side)."""
    n = RESOLUTION
    return image[:, : n // 2 - 1], image[:, n // 2 + 1 :]


def test_each_material_slot_bakes_its_own_faces(addon):
    import bpy

    plane = plane_scene([skin("Pale", PALE), skin("Dark", DARK, radius=(2.0, 1.0, 0.5))])
    both = bake()
    for slot in (0, 1):
        for polygon in plane.data.polygons:
            polygon.material_index = slot
        alone = halves(bake())[slot]
        assert np.allclose(halves(both)[slot], alone, rtol=1e-5, atol=1e-7), slot
    left, right = halves(both)
    assert left[..., 0].mean() > 2 * right[..., 0].mean()
    assert len(bpy.data.images) == 1


def test_a_slot_without_subsurface_is_left_out_and_reported(addon, capfd):
    import bpy

    glass = skin("Glass", DARK)
    glass.node_tree.nodes["Principled BSDF"].inputs["Subsurface Weight"].default_value = 0.0
    plane_scene([skin("Pale", PALE), glass])
    assert bpy.ops.sssbake.bake(resolution=RESOLUTION, method="BRUTE", outputs={"SUBSURFACE"}) == {"FINISHED"}
    out = capfd.readouterr().out
    assert "material `Glass`: Subsurface Weight is 0; its faces are left out" in out
    left, right = halves(pixels("Plane_subsurface"))
    assert (left[..., 3] == 1).all() and (right[..., 3] == 0).all()


def test_the_principled_bsdf_feeding_the_active_output_is_read(addon):
    import bpy

    material = skin("Skin", DARK)
    tree = material.node_tree
    # A second Principled, connected to the output, first in the node list.
    tree.nodes.remove(tree.nodes["Principled BSDF"])
    stray = tree.nodes.new("ShaderNodeBsdfPrincipled")
    stray.inputs["Base Color"].default_value = (0.1, 0.9, 0.1, 1.0)
    stray.inputs["Subsurface Weight"].default_value = 1.0
    wired = skin("Wired", PALE).node_tree.nodes["Principled BSDF"]
    used = tree.nodes.new("ShaderNodeBsdfPrincipled")
    for name in ("Base Color", "Subsurface Weight", "Subsurface Radius", "Subsurface Scale"):
        used.inputs[name].default_value = wired.inputs[name].default_value
    tree.links.new(used.outputs["BSDF"], tree.nodes["Material Output"].inputs["Surface"])
    # A second output that is not the active one, fed by the stray node.
    other = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(stray.outputs["BSDF"], other.inputs["Surface"])
    tree.nodes["Material Output"].is_active_output = True
    plane_scene([material], right_slot=0)
    from_tree = bake()
    bpy.data.objects["Plane"].data.materials[0] = bpy.data.materials["Wired"]
    assert np.allclose(from_tree, bake(), rtol=1e-5, atol=1e-7)


def image(folder, name, columns):
    """An 8-bit sRGB PNG of 4 rows of `columns` (sRGB codes, left to right), loaded."""
    import bpy
    from test_colour_maps import png

    return bpy.data.images.load(str(png(folder / name, [columns] * 4)))


def redness(half):
    """Red over blue, the mean over a half's texels."""
    return (half[..., 0] / half[..., 2]).mean()


def test_an_image_texture_is_read_through_its_uv_map_and_mapping(addon, tmp_path):
    from test_colour_maps import LEFT, RIGHT

    material = skin("Skin", (0.5, 0.5, 0.5))
    tree = material.node_tree
    bsdf = tree.nodes["Principled BSDF"]
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.interpolation = "Closest"
    tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    plane = plane_scene([material], right_slot=0)
    # One colour: the bake of the plain Base Color it decodes to (sRGB), texel for texel.
    texture.image = image(tmp_path, "one.png", [LEFT] * 4)
    constant = bake()
    tree.links.remove(bsdf.inputs["Base Color"].links[0])
    bsdf.inputs["Base Color"].default_value = (*(srgb_to_linear(c / 255) for c in LEFT), 1.0)
    plain = bake()
    assert np.allclose(constant, plain, rtol=1e-4, atol=1e-7)
    # Two colours, the red one on the left of the image: the left of the plane is redder.
    tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    texture.image = image(tmp_path, "two.png", [LEFT] * 2 + [RIGHT] * 2)
    direct = halves(bake())
    assert redness(direct[0]) > 2 * redness(direct[1])
    # Through a second UV map mirrored in u (a UV Map node), the halves swap.
    uv = plane.data.uv_layers.new(name="Mirrored")
    first = plane.data.uv_layers[0]
    for loop, data in zip(first.data, uv.data, strict=True):
        data.uv = (1.0 - loop.uv[0], loop.uv[1])
    plane.data.uv_layers.active = first
    node = tree.nodes.new("ShaderNodeUVMap")
    node.uv_map = "Mirrored"
    tree.links.new(node.outputs["UV"], texture.inputs["Vector"])
    mirrored = halves(bake())
    assert redness(mirrored[1]) > 2 * redness(mirrored[0])
    # A Mapping node that mirrors u back (scale −1, then 1 along x) undoes it.
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.inputs["Scale"].default_value = (-1.0, 1.0, 1.0)
    mapping.inputs["Location"].default_value = (1.0, 0.0, 0.0)
    tree.links.new(node.outputs["UV"], mapping.inputs["Vector"])
    tree.links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    remapped = halves(bake())
    for side in (0, 1):
        assert np.allclose(remapped[side], direct[side], rtol=1e-4, atol=1e-7)


def mix(tree, blend, factor, constant, image_on="A"):
    """A Mix node (colour) of `blend` with `factor`, `constant` on the other input."""
    node = tree.nodes.new("ShaderNodeMix")
    node.data_type, node.blend_type = "RGBA", blend
    inputs = {s.identifier: s for s in node.inputs}
    inputs["Factor_Float"].default_value = factor
    inputs["B_Color" if image_on == "A" else "A_Color"].default_value = (*constant, 1.0)
    return inputs[f"{image_on}_Color"], node.outputs["Result"]


def node(tree, kind, **values):
    """A colour node of `kind` with input values `values`: its Color input and its output."""
    made = tree.nodes.new(kind)
    for name, value in values.items():
        made.inputs[name].default_value = value
    return made.inputs["Color"], made.outputs["Color"]


# Colour nodes between an Image Texture and Base Color: each makes (input, output).
CHAINS = {
    "multiply": lambda tree: [mix(tree, "MULTIPLY", 0.7, (0.9, 0.5, 0.3))],
    "mix, image on B": lambda tree: [mix(tree, "MIX", 0.4, (0.2, 0.6, 0.3), image_on="B")],
    "bright/contrast": lambda tree: [node(tree, "ShaderNodeBrightContrast", Bright=0.1, Contrast=0.3)],
    "gamma, invert": lambda tree: [
        node(tree, "ShaderNodeGamma", Gamma=1.8),
        node(tree, "ShaderNodeInvert", Fac=0.25),
    ],
}


def chain_colour(tree, texture, name):
    """Links `texture` through chain `name` in `tree`; the chain's output socket."""
    output = texture.outputs["Color"]
    for step_input, step_output in CHAINS[name](tree):
        tree.links.new(output, step_input)
        output = step_output
    return output


def cycles_colour(image, name):
    """What Cycles makes of `image` (one colour) through chain `name`: the chain feeds an
    Emission shader on a probe plane whose emission Cycles bakes."""
    import bpy

    bpy.context.scene.render.engine = "CYCLES"
    bpy.context.scene.cycles.samples = 1
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0, 0, -5))
    probe = bpy.context.active_object
    material = bpy.data.materials.new("Probe")
    if material.node_tree is None:
        material.use_nodes = True
    tree = material.node_tree
    tree.nodes.remove(tree.nodes["Principled BSDF"])
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image, texture.interpolation = image, "Closest"
    emission = tree.nodes.new("ShaderNodeEmission")
    tree.links.new(chain_colour(tree, texture, name), emission.inputs["Color"])
    tree.links.new(emission.outputs["Emission"], tree.nodes["Material Output"].inputs["Surface"])
    target = tree.nodes.new("ShaderNodeTexImage")
    target.image = bpy.data.images.new("Emitted", 4, 4, float_buffer=True)
    tree.nodes.active = target
    probe.data.materials.append(material)
    bpy.ops.object.select_all(action="DESELECT")
    probe.select_set(True)
    bpy.context.view_layer.objects.active = probe
    assert bpy.ops.object.bake(type="EMIT") == {"FINISHED"}
    colour = pixels("Emitted")[..., :3].reshape(-1, 3).mean(axis=0)
    bpy.data.objects.remove(probe)
    bpy.data.images.remove(bpy.data.images["Emitted"])
    return colour


@pytest.mark.parametrize("name", CHAINS)
def test_colour_nodes_between_the_image_and_base_color_are_applied(addon, tmp_path, name):
    import bpy
    from test_colour_maps import LEFT

    material = skin("Skin", (0.5, 0.5, 0.5))
    tree = material.node_tree
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image, texture.interpolation = image(tmp_path, "one.png", [LEFT] * 4), "Closest"
    bsdf = tree.nodes["Principled BSDF"]
    tree.links.new(chain_colour(tree, texture, name), bsdf.inputs["Base Color"])
    plane_scene([material], right_slot=0)
    through_nodes = bake()
    colour = cycles_colour(texture.image, name)
    assert not np.allclose(colour, [srgb_to_linear(c / 255) for c in LEFT], atol=0.01)
    for link in bsdf.inputs["Base Color"].links:
        tree.links.remove(link)
    bsdf.inputs["Base Color"].default_value = (*colour, 1.0)
    bpy.data.objects["Plane"].select_set(True)
    bpy.context.view_layer.objects.active = bpy.data.objects["Plane"]
    assert np.allclose(through_nodes, bake(), rtol=1e-4, atol=1e-7)


def test_inputs_the_bake_does_not_follow_are_reported(addon, capfd, tmp_path):
    import bpy
    from test_colour_maps import LEFT

    muted = skin("Muted", DARK)
    texture = muted.node_tree.nodes.new("ShaderNodeTexImage")
    texture.image = image(tmp_path, "one.png", [LEFT] * 4)
    texture.mute = True
    muted.node_tree.links.new(
        texture.outputs["Color"], muted.node_tree.nodes["Principled BSDF"].inputs["Base Color"]
    )
    material = skin("Skin", PALE)
    tree = material.node_tree
    bsdf = tree.nodes["Principled BSDF"]
    checker = tree.nodes.new("ShaderNodeTexChecker")
    tree.links.new(checker.outputs["Color"], bsdf.inputs["Base Color"])
    noise = tree.nodes.new("ShaderNodeTexNoise")
    tree.links.new(noise.outputs["Fac"], bsdf.inputs["Subsurface Scale"])
    plane_scene([material, muted])
    assert bpy.ops.sssbake.bake(resolution=16, method="BRUTE", outputs={"SUBSURFACE"}) == {"FINISHED"}
    out = capfd.readouterr().out
    assert (
        "Base Color is driven by `Checker Texture` (Checker Texture), which the add-on does not read" in out
    )
    assert "Subsurface Scale is driven by `Noise Texture` (Noise Texture), which is not applied" in out
    assert "material `Muted`: Base Color is driven by `Image Texture` (Image Texture), which is muted" in out
