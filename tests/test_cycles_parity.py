"""A Blender skin bakes as Cycles renders it. A thick slab with the bundled head's skin
(Principled, Random Walk, Base Color (0.8, 0.55, 0.45), Radius (1, 0.35, 0.2), Scale 2 mm,
IOR 1.4) lies half in the hard shadow of a plane under a sun. Cycles bakes its diffuse pass
(which holds the subsurface light) and the add-on bakes the same scene through the library;
the shadow edge's blur must have the same widths and the lit side the same level.

The slab's top carries a square 8 mm across the shadow edge mapped onto the image at 1/64 mm
per texel; the rest of the slab is mapped outside the image, so neither baker writes it (nor,
in sssbake, scatters its light: the square reaches 3 mm past the rows measured, farther than
the red light travels). Cycles' noise is averaged along the edge."""

import numpy as np
from skin_material import principled_skin
from test_blender_addon import pixels

MM = 0.001
RESOLUTION = 512
STRIP_MM = (8.0, 8.0)
CYCLES_SAMPLES = 16


def slab_scene():
    """The slab (20 × 20 × 10 mm, closed), the occluder over x < 0 seen only by shadow rays,
    a sun straight down of 1 W/m², no world; the slab selected."""
    import bpy

    xs, ys = (-10, -4, 4, 10), (-10, -4, 4, 10)
    top = [(x * MM, y * MM, 0.0) for y in ys for x in xs]
    bottom = [(x * MM, y * MM, -10 * MM) for x, y in ((-10, -10), (10, -10), (10, 10), (-10, 10))]

    def t(i, j):
        return j * 4 + i

    b = len(top)
    faces = [(t(i, j), t(i + 1, j), t(i + 1, j + 1), t(i, j + 1)) for j in range(3) for i in range(3)]
    faces += [
        (b + 3, b + 2, b + 1, b),
        (b, b + 1, t(3, 0), t(2, 0), t(1, 0), t(0, 0)),
        (b + 1, b + 2, t(3, 3), t(3, 2), t(3, 1), t(3, 0)),
        (b + 2, b + 3, t(0, 3), t(1, 3), t(2, 3), t(3, 3)),
        (b + 3, b, t(0, 0), t(0, 1), t(0, 2), t(0, 3)),
    ]
    mesh = bpy.data.meshes.new("Slab")
    mesh.from_pydata(top + bottom, [], faces)
    uv = mesh.uv_layers.new(name="UVMap")
    strip = 4  # the middle face of the top
    for polygon in mesh.polygons:
        for loop in polygon.loop_indices:
            co = mesh.vertices[mesh.loops[loop].vertex_index].co
            if polygon.index == strip:
                uv.data[loop].uv = ((co.x / MM + 4) / 8, (co.y / MM + 4) / 8)
            else:
                uv.data[loop].uv = (1.5 + 0.01 * polygon.index, 1.5)
    slab = bpy.data.objects.new("Slab", mesh)
    bpy.context.scene.collection.objects.link(slab)
    material = principled_skin(2 * MM, ior=1.4, method="RANDOM_WALK")
    slab.data.materials.append(material)

    corners = [
        (-60 * MM, -60 * MM, 3 * MM),
        (0, -60 * MM, 3 * MM),
        (0, 60 * MM, 3 * MM),
        (-60 * MM, 60 * MM, 3 * MM),
    ]
    occluder_mesh = bpy.data.meshes.new("Occluder")
    occluder_mesh.from_pydata(corners, [], [(0, 1, 2, 3)])
    occluder = bpy.data.objects.new("Occluder", occluder_mesh)
    bpy.context.scene.collection.objects.link(occluder)
    # A black body for every ray but shadow rays: no light bounces back onto the slab.
    for ray in ("camera", "diffuse", "glossy", "transmission", "volume_scatter"):
        setattr(occluder, f"visible_{ray}", False)
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy, sun.angle = 1.0, 0.0
    bpy.context.scene.collection.objects.link(bpy.data.objects.new("Sun", sun))

    bpy.ops.object.select_all(action="DESELECT")
    slab.select_set(True)
    bpy.context.view_layer.objects.active = slab
    return slab, material


def cycles_exitance(material, resolution=RESOLUTION, samples=CYCLES_SAMPLES):
    """Cycles' diffuse pass (radiance of a Lambertian exit, W/(m²·sr)) × π: the exitance, as a
    `resolution`² image at `samples` samples per texel."""
    import bpy

    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.seed = 1
    image = bpy.data.images.new("cycles", resolution, resolution, alpha=True, float_buffer=True)
    # Transparent until baked: the bake's alpha then marks the texels it wrote.
    image.generated_color = (0.0, 0.0, 0.0, 0.0)
    node = material.node_tree.nodes.new("ShaderNodeTexImage")
    node.image = image
    material.node_tree.nodes.active = node
    bpy.ops.object.bake(type="DIFFUSE", pass_filter={"DIRECT", "INDIRECT", "COLOR"}, margin=0)
    material.node_tree.nodes.remove(node)
    return pixels("cycles") * np.pi


def baked_exitance(name):
    """The add-on's `diffuse` map of object `name` × π, to set beside `cycles_exitance`: both
    weigh the light leaving by the specular layer once, where the surface is viewed."""
    return pixels(f"{name}_diffuse") * np.pi


def across_the_edge(image):
    """The map averaged along the edge (y) over the square's middle 2 mm, per x: (x mm, rgb)."""
    rows = image[3 * RESOLUTION // 8 : 5 * RESOLUTION // 8, :, :3]
    x = (np.arange(RESOLUTION) + 0.5) / RESOLUTION * STRIP_MM[0] - STRIP_MM[0] / 2
    return x, rows.mean(axis=0)


def reach(x, profile, level):
    """How far into the shadow (x < 0, mm) the profile stays above `level` of its lit level."""
    lit = profile[(x > 2.0) & (x < 3.0)].mean()
    above = np.nonzero(profile > level * lit)[0][0]
    return -np.interp(level * lit, profile[above - 1 : above + 1], x[above - 1 : above + 1])


def test_a_principled_skin_bakes_as_cycles_renders_it(addon):
    import bpy

    _, material = slab_scene()
    assert bpy.ops.sssbake.bake(resolution=RESOLUTION, uv_map="UVMap", outputs={"DIFFUSE"}) == {"FINISHED"}
    x, ours = across_the_edge(baked_exitance("Slab"))
    _, cycles = across_the_edge(cycles_exitance(material))

    texel = STRIP_MM[0] / RESOLUTION
    rows, wrong = [], []
    for c, name in enumerate("RGB"):
        lit_ours, lit_cycles = (p[(x > 2.0) & (x < 3.0), c].mean() for p in (ours, cycles))
        rows.append(f"{name} lit level: ours {lit_ours:.4f}, Cycles {lit_cycles:.4f} W/m²")
        if abs(lit_ours / lit_cycles - 1) > 0.10:
            wrong.append(rows[-1])
        for level in (0.1, 0.01):
            width_cycles = reach(x, cycles[:, c], level)
            width_ours = reach(x, ours[:, c], level)
            rows.append(
                f"{name} reach at {level:.0%}: ours {width_ours:.3f} mm, Cycles {width_cycles:.3f} mm"
            )
            # Only what the texels resolve is compared: eight texels or more.
            if width_cycles >= 8 * texel and abs(width_ours / width_cycles - 1) > 0.30:
                wrong.append(rows[-1])
    print("\n".join(rows))
    assert not wrong, "\n".join(rows)
