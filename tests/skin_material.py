"""Blender's skin as the tests and scripts set it up: a Principled BSDF with Base Color
(0.8, 0.55, 0.45), full Subsurface Weight and Radius (1, 0.35, 0.2)."""


def principled_skin(scale, ior=None, roughness=None, method=None):
    """A new material `Skin` at Subsurface Scale `scale` (scene units); `ior`, `roughness` and
    the subsurface `method` are set where given, Blender's defaults kept otherwise."""
    import bpy

    material = bpy.data.materials.new("Skin")
    if material.node_tree is None:  # Blender before 5 makes node trees on request
        material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.8, 0.55, 0.45, 1.0)
    bsdf.inputs["Subsurface Weight"].default_value = 1.0
    bsdf.inputs["Subsurface Radius"].default_value = (1.0, 0.35, 0.2)
    bsdf.inputs["Subsurface Scale"].default_value = scale
    if ior is not None:
        bsdf.inputs["IOR"].default_value = ior
    if roughness is not None:
        bsdf.inputs["Roughness"].default_value = roughness
    if method is not None:
        bsdf.subsurface_method = method
    return material
