"""Right against light: a backlit 3 mm slab of Blender's default skin (Principled, Random
Walk, Base Color (0.8, 0.55, 0.45), Radius (1, 0.35, 0.2), Scale 0.05, IOR 1.4) under a sun
from below. Cycles bakes its diffuse pass; the add-on bakes the same scene by the volumetric
walk and by its default method (the corrected model: the level of light, thin parts by the
local slab). Over the slab's middle, away from its rim, the lit face and the far face (which
sees only the light that crossed the 3 mm) are compared with Cycles':

- the walk is Cycles' own transport (a walk starting straight in, as Cycles' Random Walk
  enters for a bake's view along the normal, scoring the irradiance where it leaves): within
  3% in every channel, on both faces;
- the default bake within 3% too (measured: 1.007 / 1.009 / 1.014 on the far face, 1.006 /
  1.001 / 0.998 on the lit one). Red's diffusion length 1/σtr at this reach (25 mm, for a
  mean free path of 4 mm) is most of the slab's 30 mm side. The slab's faces gather with its
  own slab's profile, which spreads light as a slab does. The map is light's radiance along
  the normal, whose power over this slab is more than entered (red: 1.075 of it by the walk);
  scaled down to the power entering, red was 0.95 on both faces.

The top face is mapped onto the left half of the image, the bottom face onto the right
half; the rim onto a strip along the bottom edge, outside what is compared. Cycles' noise
is averaged over the compared region."""

import numpy as np
import pytest
from skin_material import principled_skin
from test_cycles_parity import baked_exitance, cycles_exitance

MM = 0.001
SIDE_MM = 30.0
THICK_MM = 3.0
RESOLUTION = 128
SAMPLES = 64


def backlit_slab():
    """The slab (closed, 30 × 30 × 3 mm) in skin at Blender's default reach, a sun straight
    up from below of 1 W/m², no world; the slab selected."""
    import bpy

    h, t = SIDE_MM / 2 * MM, THICK_MM * MM
    corners = [(-h, -h), (h, -h), (h, h), (-h, h)]
    vertices = [(x, y, t) for x, y in corners] + [(x, y, 0.0) for x, y in corners]
    faces = [(0, 1, 2, 3), (7, 6, 5, 4), (0, 4, 5, 1), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 4, 0)]
    mesh = bpy.data.meshes.new("Slab")
    mesh.from_pydata(vertices, [], faces)
    uv = mesh.uv_layers.new(name="UVMap")
    for polygon in mesh.polygons:
        for loop in polygon.loop_indices:
            co = mesh.vertices[mesh.loops[loop].vertex_index].co
            u, v = (co.x + h) / (2 * h), (co.y + h) / (2 * h)
            if polygon.index == 0:  # top: the left half, above the rim's strip
                uv.data[loop].uv = (0.02 + 0.46 * u, 0.1 + 0.88 * v)
            elif polygon.index == 1:  # bottom: the right half
                uv.data[loop].uv = (0.52 + 0.46 * u, 0.1 + 0.88 * v)
            else:  # the rim: a strip of its own along the bottom
                side = polygon.index - 2
                along = u if side in (0, 2) else v
                uv.data[loop].uv = (0.25 * side + 0.02 + 0.2 * along, 0.02 + 0.05 * (co.z / t))
    slab = bpy.data.objects.new("Slab", mesh)
    bpy.context.scene.collection.objects.link(slab)
    material = principled_skin(0.05, ior=1.4, method="RANDOM_WALK")
    slab.data.materials.append(material)

    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy, sun.angle = 1.0, 0.0
    sun_object = bpy.data.objects.new("Sun", sun)
    sun_object.rotation_euler = (np.pi, 0.0, 0.0)  # shining straight up
    bpy.context.scene.collection.objects.link(sun_object)
    if bpy.context.scene.world is not None:
        bpy.context.scene.world = None

    bpy.ops.object.select_all(action="DESELECT")
    slab.select_set(True)
    bpy.context.view_layer.objects.active = slab
    return material


def middles(image):
    """The mean over each face's middle (within 9 mm of its centre) of an image: (top, bottom)."""
    n = RESOLUTION
    v = (np.arange(n) + 0.5) / n
    rows = np.abs((v - 0.1) / 0.88 - 0.5) * SIDE_MM < 9.0

    def face(left):
        u = (v - left) / 0.46
        columns = np.abs(u - 0.5) * SIDE_MM < 9.0
        return image[np.ix_(rows, columns)][..., :3].reshape(-1, 3).mean(axis=0)

    return face(0.02), face(0.52)


@pytest.mark.parametrize("method", ["AUTO", "WALK"])
def test_a_backlit_skin_slab_sends_cycles_light_through(addon, method):
    import bpy

    material = backlit_slab()
    bpy.context.scene.sssbake.method = method
    assert bpy.ops.sssbake.bake(resolution=RESOLUTION, uv_map="UVMap", outputs={"DIFFUSE"}) == {"FINISHED"}
    ours = middles(baked_exitance("Slab"))
    cycles = middles(cycles_exitance(material, RESOLUTION, SAMPLES))
    tolerance = np.array([0.03] * 3)
    rows, wrong = [], []
    for face, name in enumerate(("far face (top)", "lit face (bottom)")):
        ratio = ours[face] / cycles[face]
        rows.append(
            f"{method} {name}: ours {np.round(ours[face], 5)}, Cycles {np.round(cycles[face], 5)}, "
            f"ratio {np.round(ratio, 3)}"
        )
        if np.any(np.abs(ratio - 1) > tolerance):
            wrong.append(rows[-1])
    print("\n".join(rows))
    assert not wrong, "\n".join(rows)
