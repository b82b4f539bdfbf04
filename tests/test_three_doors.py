"""One Blender scene through the three doors: baked by the add-on, and exported by Blender
to glTF and to USD and baked by the CLI, it gives the same irradiance and subsurface maps
(relative difference texel for texel over covered texels: median within 1 %, 95th
percentile within 3 %).

The scene: a 60 mm plane with a Principled Random Walk material whose Base Color is an
Image Texture of two colours (an 8-bit sRGB PNG), lit by a sun, a point, a spot (with a
blend band) and a rectangular area light, and a plane over half of it hidden from renders
but shown in the viewport (it must cast no shadow).

What each door can carry, and how the scene is built for it:
- Blender's exporters leave out the subsurface inputs; the test writes them into each file
  by the format's own definition (glTF `KHR_materials_volume` with `KHR_materials_ior`,
  USD OpenPBR reading the exported `UsdUVTexture`), as `examples/make_examples.py` does.
  IOR is 1: the formats read the boundary at the IOR where Cycles' Random Walk is
  index-matched (docs/materials.md, "Materials from Blender"), so only at IOR 1 do all three describe
  one medium. The add-on bakes with *Physical* colour to albedo, the inversion the formats'
  readers use.
- glTF's punctual lights have no size and glTF has no area lights: the point and spot have
  radius 0 and the sun angle 0, and the glTF bake is compared with an add-on bake that
  leaves the area light out (hidden from renders); USD carries all four.
- The hidden plane: the glTF exporter is asked for renderable objects only (its default
  exports objects hidden from renders); Blender's USD exporter leaves it out on its own.
"""

import json
import math

import numpy as np
import pytest
from conftest import bake_summary, exr
from test_blender_addon import pixels
from test_colour_maps import LEFT, RIGHT, png

MM = 0.001
RESOLUTION = 64
RADIUS = (1.0, 0.5, 0.25)
SCALE = 2 * MM
IOR = 1.0


def build_scene(folder):
    """The scene of the module's docstring, the plane selected; returns the area light."""
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.unit_settings.system = "METRIC"
    bpy.ops.mesh.primitive_plane_add(size=60 * MM)
    plane = bpy.context.active_object
    plane.name = "Plane"
    material = bpy.data.materials.new("Skin")
    if material.node_tree is None:
        material.use_nodes = True
    nodes = material.node_tree.nodes
    bsdf = nodes["Principled BSDF"]
    bsdf.subsurface_method = "RANDOM_WALK"
    bsdf.inputs["Subsurface Weight"].default_value = 1.0
    bsdf.inputs["Subsurface Radius"].default_value = RADIUS
    bsdf.inputs["Subsurface Scale"].default_value = SCALE
    bsdf.inputs["IOR"].default_value = IOR
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = bpy.data.images.load(str(png(folder / "two.png", [[LEFT] * 4 + [RIGHT] * 4] * 8)))
    material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    plane.data.materials.append(material)

    def light(kind, name, location, rotation, energy, **settings):
        data = bpy.data.lights.new(name, kind)
        data.energy = energy
        for key, value in settings.items():
            setattr(data, key, value)
        obj = bpy.data.objects.new(name, data)
        obj.location, obj.rotation_euler = location, rotation
        bpy.context.scene.collection.objects.link(obj)
        return obj

    light("SUN", "Sun", (0, 0, 1), (0.3, 0.2, 0.0), 2.0, angle=0.0)
    light("POINT", "Point", (20 * MM, 5 * MM, 40 * MM), (0, 0, 0), 0.05, shadow_soft_size=0.0)
    light(
        "SPOT",
        "Spot",
        (-15 * MM, 0, 50 * MM),
        (0.3, 0, 0),
        0.1,
        shadow_soft_size=0.0,
        spot_size=math.radians(50),
        spot_blend=0.3,
    )
    area = light("AREA", "Area", (0, -20 * MM, 40 * MM), (-0.4, 0, 0), 0.05, size=20 * MM)
    bpy.ops.mesh.primitive_plane_add(size=40 * MM, location=(20 * MM, 0, 10 * MM))
    bpy.context.active_object.name = "Hidden"
    bpy.context.active_object.hide_render = True
    bpy.ops.object.select_all(action="DESELECT")
    plane.select_set(True)
    bpy.context.view_layer.objects.active = plane
    return area


def addon_maps():
    """The add-on's irradiance and subsurface maps of the plane, rows top to bottom."""
    import bpy

    result = bpy.ops.sssbake.bake(
        resolution=RESOLUTION,
        method="BRUTE",
        quality="FINAL",
        albedo_mapping="PHYSICAL",
        outputs={"IRRADIANCE", "SUBSURFACE"},
    )
    assert result == {"FINISHED"}
    return {output: pixels(f"Plane_{output}")[::-1] for output in ("irradiance", "subsurface")}


def cli_maps(sssbake, scene, out):
    """The CLI's maps of the plane from `scene`, rows top to bottom, with alpha from coverage."""
    summary = bake_summary(
        sssbake,
        scene,
        out,
        "--resolution",
        str(RESOLUTION),
        "--method",
        "brute",
        "--light-samples",
        "64",
        "--uvs",
        "keep",
        "--outputs",
        "irradiance,subsurface",
    )
    (plane,) = [o for o in summary["objects"] if o["name"] == "Plane"]
    return {o: exr(out / f"{plane['file_stem']}_{o}.exr") for o in ("irradiance", "subsurface")}, summary


def add_gltf_subsurface(path):
    """The plane's material as a glTF volume: mean free path Radius × Scale / 4π, IOR 1."""
    document = json.loads(path.read_text())
    (material,) = document["materials"]
    extensions = material.setdefault("extensions", {})
    extensions["KHR_materials_ior"] = {"ior": IOR}
    extensions["KHR_materials_volume"] = {
        "thicknessFactor": SCALE,
        "attenuationDistance": SCALE / (4 * math.pi),
        "attenuationColor": [math.exp(-1.0 / r) for r in RADIUS],
    }
    used = document.setdefault("extensionsUsed", [])
    used += [e for e in extensions if e not in used]
    path.write_text(json.dumps(document, indent=2))


def add_usd_subsurface(path):
    """An OpenPBR surface beside Blender's UsdPreviewSurface, its subsurface colour read from
    the texture Blender exported."""
    from pxr import Gf, Sdf, Usd, UsdShade

    stage = Usd.Stage.Open(str(path))
    (prim,) = [p for p in stage.Traverse() if p.IsA(UsdShade.Material)]
    texture = next(
        UsdShade.Shader(p)
        for p in prim.GetChildren()
        if UsdShade.Shader(p).GetIdAttr().Get() == "UsdUVTexture"
    )
    shader = UsdShade.Shader.Define(stage, prim.GetPath().AppendChild("OpenPBR"))
    shader.CreateIdAttr("ND_open_pbr_surface_surfaceshader")
    for name, kind, value in [
        ("subsurface_weight", Sdf.ValueTypeNames.Float, 1.0),
        ("subsurface_radius", Sdf.ValueTypeNames.Float, SCALE / (4 * math.pi)),
        ("subsurface_radius_scale", Sdf.ValueTypeNames.Color3f, Gf.Vec3f(*RADIUS)),
        ("specular_ior", Sdf.ValueTypeNames.Float, IOR),
    ]:
        shader.CreateInput(name, kind).Set(value)
    for name in ("base_color", "subsurface_color"):
        shader.CreateInput(name, Sdf.ValueTypeNames.Color3f).ConnectToSource(texture.GetOutput("rgb"))
    output = shader.CreateOutput("out", Sdf.ValueTypeNames.Token)
    UsdShade.Material(prim).CreateSurfaceOutput("mtlx").ConnectToSource(output)
    stage.Save()


def relative_differences(ours, theirs):
    """|ours − theirs| / theirs per channel over texels both cover and light."""
    covered = (ours[..., 3] > 0) if ours.shape[-1] == 4 else np.ones(ours.shape[:2], bool)
    a, b = ours[..., :3][covered], theirs[..., :3][covered]
    lit = b > 1e-6 * b.max()
    return np.abs(a - b)[lit] / b[lit]


def assert_agree(ours, theirs, what):
    difference = relative_differences(ours, theirs)
    median, p95 = np.median(difference), np.percentile(difference, 95)
    assert median <= 0.01 and p95 <= 0.03, f"{what}: median {median:.4f}, 95th percentile {p95:.4f}"


@pytest.mark.usefixtures("addon")
def test_one_scene_bakes_the_same_maps_through_the_addon_gltf_and_usd(sssbake, tmp_path):
    import bpy

    area = build_scene(tmp_path)
    with_area = addon_maps()
    bpy.ops.wm.usd_export(filepath=str(tmp_path / "scene.usda"))
    area.hide_render = True
    without_area = addon_maps()
    bpy.ops.export_scene.gltf(
        filepath=str(tmp_path / "scene.gltf"),
        export_format="GLTF_SEPARATE",
        export_lights=True,
        use_renderable=True,
    )
    add_gltf_subsurface(tmp_path / "scene.gltf")
    add_usd_subsurface(tmp_path / "scene.usda")
    from_gltf, gltf_summary = cli_maps(sssbake, tmp_path / "scene.gltf", tmp_path / "gltf")
    from_usd, usd_summary = cli_maps(sssbake, tmp_path / "scene.usda", tmp_path / "usd")
    for summary in (gltf_summary, usd_summary):
        (plane,) = [o for o in summary["objects"] if o["name"] == "Plane"]
        assert plane["colour"]["source"] == "texture", plane["colour"]
    assert len(usd_summary["lights"]) == 4, usd_summary["lights"]
    assert len(gltf_summary["lights"]) == 3, gltf_summary["lights"]
    for output in ("irradiance", "subsurface"):
        assert_agree(with_area[output], from_usd[output], f"add-on against USD, {output}")
        assert_agree(without_area[output], from_gltf[output], f"add-on against glTF, {output}")
    # The texture's two colours show: the left half is redder than the right.
    subsurface = with_area["subsurface"]
    left, right = subsurface[:, : RESOLUTION // 4, :3], subsurface[:, -RESOLUTION // 4 :, :3]
    assert (left[..., 0] / left[..., 2]).mean() > 2 * (right[..., 0] / right[..., 2]).mean()
