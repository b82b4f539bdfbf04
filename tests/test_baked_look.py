"""The baked look, lit once: the head baked from its glTF and from its USD file. The USD
layer's variant set shows the linear EXR as emission and switches back to the asset's own
material; the glTF copy's emissive PNG does not clip and its strength restores the map; and
Blender imports both and renders the bake at the map's brightness."""

import json
import math
import pathlib
import subprocess

import numpy as np
import pytest
from conftest import ROOT, bake_summary, exr, png_rgb, run, srgb_to_linear, usd_validation_errors
from traced_view import assert_shows, nothing_outside, radiance_at, smooth_pixels

HEAD = ROOT / "examples" / "head"
RESOLUTION = 128


@pytest.fixture(scope="module")
def gltf_bake(sssbake, tmp_path_factory):
    out = tmp_path_factory.mktemp("look-gltf")
    summary = bake_summary(sssbake, HEAD / "head.gltf", out, "--resolution", str(RESOLUTION))
    return out, summary


@pytest.fixture(scope="module")
def usd_bake(sssbake, tmp_path_factory):
    out = tmp_path_factory.mktemp("look-usd")
    summary = bake_summary(sssbake, HEAD / "head.usda", out, "--resolution", str(RESOLUTION))
    return out, summary


@pytest.fixture(scope="module")
def version(sssbake):
    """The binary's version, as `sssbake --version` prints it."""
    result = run(sssbake, "--version")
    assert result.returncode == 0, result.stderr
    return result.stdout.split()[-1]


# (a) The USD layer.


def test_the_usd_layer_selects_the_baked_look_and_switches_back(usd_bake, version):
    from pxr import Sdf, Usd, UsdShade

    out, summary = usd_bake
    layer = out / "head_sssbake.usda"
    stage = Usd.Stage.Open(str(layer))
    mesh = stage.GetPrimAtPath("/root/Head/Suzanne")
    looks = mesh.GetVariantSets().GetVariantSet("sssbakeLook")
    assert sorted(looks.GetVariantNames()) == ["baked", "original"]
    assert looks.GetVariantSelection() == "baked"

    material, _ = UsdShade.MaterialBindingAPI(mesh).ComputeBoundMaterial()
    assert material.GetPath() == Sdf.Path("/root/SssbakeMaterials/Head")
    surface = material.ComputeSurfaceSource()[0]
    assert surface.GetIdAttr().Get() == "UsdPreviewSurface"
    assert tuple(surface.GetInput("diffuseColor").Get()) == (0, 0, 0)
    assert not surface.GetInput("diffuseColor").HasConnectedSource()
    assert surface.GetInput("useSpecularWorkflow").Get() == 1
    assert tuple(surface.GetInput("specularColor").Get()) == (0, 0, 0)
    (source,) = surface.GetInput("emissiveColor").GetConnectedSources()[0]
    texture = UsdShade.Shader(source.source.GetPrim())
    assert texture.GetIdAttr().Get() == "UsdUVTexture"
    assert source.sourceName == "rgb"
    assert texture.GetInput("file").Get().path == "Head_diffuse.exr"
    assert (out / "Head_diffuse.exr").exists()
    assert texture.GetInput("sourceColorSpace").Get() == "raw"
    (uv,) = texture.GetInput("st").GetConnectedSources()[0]
    reader = UsdShade.Shader(uv.source.GetPrim())
    varname = reader.GetInput("varname").Get()
    assert varname == "st" and mesh.HasAttribute(f"primvars:{varname}")

    # Provenance, from the bake's summary.
    baked = summary["objects"][0]
    prim = material.GetPrim()
    assert prim.GetAttribute("sssbake:method").Get() == baked["integrator"]["method"]
    assert prim.GetAttribute("sssbake:resolution").Get() == str(RESOLUTION)
    assert prim.GetAttribute("sssbake:material").Get() == baked["material"]["name"]
    assert prim.GetAttribute("sssbake:material_source").Get() == baked["material"]["source"]
    assert prim.GetAttribute("sssbake:version").Get() == version

    assert usd_validation_errors(stage) == []

    # `original` is the asset as it was: its own material, and no sssbake UVs or bindings.
    looks.SetVariantSelection("original")
    original, _ = UsdShade.MaterialBindingAPI(mesh).ComputeBoundMaterial()
    source_stage = Usd.Stage.Open(str(HEAD / "head.usda"))
    own, _ = UsdShade.MaterialBindingAPI(
        source_stage.GetPrimAtPath("/root/Head/Suzanne")
    ).ComputeBoundMaterial()
    assert original.GetPath() == own.GetPath() == Sdf.Path("/root/_materials/Skin")
    assert not [p for p in mesh.GetAuthoredPropertyNames() if "sssbake" in p.lower()]


def test_the_baked_variant_wins_over_an_explicit_schema_list(sssbake, tmp_path):
    """An exported (flattened) stage writes `apiSchemas` as an explicit list, a stronger
    opinion than any variant: the layer still binds the bake, and `original` still undoes it."""
    from pxr import Sdf, Usd, UsdShade

    scene = tmp_path / "exported.usda"
    Usd.Stage.Open(str(ROOT / "examples" / "marble" / "marble.usda")).Export(str(scene))
    assert 'apiSchemas = ["MaterialBindingAPI"]' in scene.read_text()
    bake_summary(sssbake, scene, tmp_path / "out", "--resolution", "32")
    stage = Usd.Stage.Open(str(tmp_path / "out" / "exported_sssbake.usda"))
    mesh = stage.GetPrimAtPath("/root/Ball/Sphere")
    material, _ = UsdShade.MaterialBindingAPI(mesh).ComputeBoundMaterial()
    assert material.GetPath() == Sdf.Path("/root/SssbakeMaterials/Ball")
    mesh.GetVariantSet("sssbakeLook").SetVariantSelection("original")
    material, _ = UsdShade.MaterialBindingAPI(mesh).ComputeBoundMaterial()
    assert material.GetPath() == Sdf.Path("/root/_materials/Marble")


# (b) The glTF copy.


def baked_material(copy: dict) -> dict:
    """The head's material in the copy, checked to be the one its mesh uses."""
    (index,) = [i for i, m in enumerate(copy["materials"]) if m["name"] == "Head (sssbake)"]
    (node,) = [n for n in copy["nodes"] if n.get("name") == "Head"]
    assert {p["material"] for p in copy["meshes"][node["mesh"]]["primitives"]} == {index}
    return copy["materials"][index]


def test_the_gltf_copy_emits_the_map_unclipped_at_its_strength(gltf_bake, version):
    out, _ = gltf_bake
    copy = json.loads((out / "head.gltf").read_text())
    assert copy["asset"]["generator"].startswith(f"sssbake {version}")
    material = baked_material(copy)
    pbr = material["pbrMetallicRoughness"]
    assert pbr["baseColorFactor"] == [0, 0, 0, 1] and "baseColorTexture" not in pbr
    assert (pbr["metallicFactor"], pbr["roughnessFactor"]) == (0, 1)
    assert material["emissiveFactor"] == [1, 1, 1]
    assert material["extensions"]["KHR_materials_specular"]["specularFactor"] == 0
    strength = material["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"]
    texture = copy["textures"][material["emissiveTexture"]["index"]]
    assert copy["images"][texture["source"]]["uri"] == "Head_diffuse_emissive.png"
    for extension in ("KHR_materials_emissive_strength", "KHR_materials_specular"):
        assert extension in copy["extensionsUsed"]
        assert extension not in copy.get("extensionsRequired", [])

    diffuse = exr(out / "Head_diffuse.exr").astype(np.float64)
    assert strength == pytest.approx(diffuse.max(), rel=1e-6)
    # The strength is what makes the range fit: the map goes well beyond 1.
    assert strength > 1.5
    codes = png_rgb(out / "Head_diffuse_emissive.png")
    assert codes.shape == diffuse.shape
    # 255 only where the map rounds to its maximum; nothing clips.
    at_maximum = diffuse / strength >= srgb_to_linear(254.5 / 255)
    assert (codes == 255).any()
    assert (codes[~at_maximum] < 255).all()
    # The PNG (sRGB) times the strength is the map, within half an 8-bit step.
    decoded = srgb_to_linear(codes / 255) * strength
    bright = diffuse > 0.05 * strength
    assert bright.sum() > 5000
    relative = np.abs(decoded[bright] - diffuse[bright]) / diffuse[bright]
    assert relative.max() < 0.02, relative.max()
    # The preview beside it, for people, keeps its sRGB clip at 1.
    assert (png_rgb(out / "Head_diffuse.png") == 255).mean() > (codes == 255).mean()


def test_the_gltf_copy_passes_the_khronos_validator(gltf_bake):
    out, _ = gltf_bake
    assert (ROOT / ".node" / "node_modules" / "gltf-validator").exists()
    result = subprocess.run(
        ["node", str(ROOT / "tests" / "validate_gltf.js"), str(out / "head.gltf")],
        capture_output=True,
        text=True,
        check=False,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    # The validator knows both extensions the copy adds, so it checked their values.
    unknown = [m["message"] for m in report["issues"]["messages"] if m["code"] == "UNSUPPORTED_EXTENSION"]
    ours = ("KHR_materials_emissive_strength", "KHR_materials_specular")
    assert not [m for m in unknown if any(e in m for e in ours)], unknown
    assert set(report["info"]["extensionsUsed"]) >= set(ours)


# (c) Blender imports both and renders the bake at the map's brightness.


def render_view(bpy, engine: str, path: pathlib.Path, size: int) -> np.ndarray:
    """The scene from its camera by `engine` (Cycles or EEVEE), size × size pixels, into a
    linear RGBA EXR with a transparent film and a black world; rows top to bottom. Both
    engines' film filters are narrowed to 0.01 pixel."""
    import OpenEXR

    scene = bpy.context.scene
    world = bpy.data.worlds.new("Black")
    world.color = (0, 0, 0)
    scene.world = world
    scene.render.engine = engine
    scene.render.film_transparent = True
    scene.cycles.device = "CPU"
    scene.cycles.samples = 4
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.cycles.filter_width = 0.01
    scene.eevee.taa_render_samples = 64
    scene.render.filter_size = 0.01
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_mode = "RGBA"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    return OpenEXR.File(str(path)).parts[0].channels["RGBA"].pixels.astype(np.float64)


def render_flat(bpy, material, uv_name: str, path: pathlib.Path, engine: str) -> np.ndarray:
    """`material` on a 2 × 2 square whose UVs span [0, 1]², seen square-on by an
    orthographic camera that puts one pixel on each texel, rendered by `engine` (Cycles or
    EEVEE) with no lights and a black world into a linear EXR; rows top to bottom."""
    scene = bpy.context.scene
    for other in scene.objects:
        other.hide_render = True
    mesh = bpy.data.meshes.new("Flat")
    corners = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    mesh.from_pydata(corners, [], [(0, 1, 2, 3)])
    uvs = mesh.uv_layers.new(name=uv_name)
    for loop in mesh.loops:
        x, y, _ = corners[loop.vertex_index]
        uvs.data[loop.index].uv = ((x + 1) / 2, (y + 1) / 2)
    mesh.materials.append(material)
    flat = bpy.data.objects.new("Flat", mesh)
    scene.collection.objects.link(flat)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = 2.0
    camera.location = (0, 0, 5)
    scene.collection.objects.link(camera)
    scene.camera = camera
    return render_view(bpy, engine, path, RESOLUTION)[..., :3]


def assert_renders_the_map(rendered: np.ndarray, diffuse: np.ndarray, tolerance: float):
    """The rendered pixels match the map's texels where the map is smooth (a pixel
    centre sits on a texel centre; a 3 × 3 neighbourhood within 10% of each other, away
    from chart edges and the image's border) and bright (a tenth of the maximum or more)."""
    assert rendered.shape == diffuse.shape
    padded = np.pad(diffuse, ((1, 1), (1, 1), (0, 0)), mode="edge")
    windows = np.stack(
        [padded[y : y + diffuse.shape[0], x : x + diffuse.shape[1]] for y in range(3) for x in range(3)]
    )
    smooth = (windows.max(axis=0) <= 1.1 * windows.min(axis=0)).all(axis=2)
    chosen = smooth & (diffuse.min(axis=2) > 0.1 * diffuse.max())
    # Not the square's outer pixels: EEVEE's jittered film samples reach past its edge.
    chosen[[0, -1], :] = chosen[:, [0, -1]] = False
    assert chosen.sum() > 200, chosen.sum()
    relative = np.abs(rendered[chosen] - diffuse[chosen]) / diffuse[chosen]
    assert np.median(relative) < tolerance / 3, np.median(relative)
    assert relative.max() < tolerance, relative.max()


def as_rendered(diffuse: np.ndarray, engine: str) -> np.ndarray:
    """The map as `engine` shows it one pixel per texel. Cycles, its filter narrowed to
    0.01 pixel, samples texel centres. EEVEE's film, at the same filter size, still spreads
    each pixel onto its neighbours: weights 0.2, 0.6, 0.2 along each axis fit its renders
    of the head's map within 0.25% (0.125, the pixel's own area, leaves 1.4%)."""
    if engine == "CYCLES":
        return diffuse
    side = 0.2
    padded = np.pad(diffuse, ((1, 1), (1, 1), (0, 0)), mode="edge")
    rows = (padded[:, :-2] + padded[:, 2:]) * side + padded[:, 1:-1] * (1 - 2 * side)
    return (rows[:-2] + rows[2:]) * side + rows[1:-1] * (1 - 2 * side)


def principled(material):
    (node,) = [n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED"]
    return node


def uv_map_name(material) -> str:
    names = [n.uv_map for n in material.node_tree.nodes if n.type == "UVMAP" and n.uv_map]
    return names[0] if names else "UVMap"


# EEVEE compiles its shaders in software here (no GPU); Cycles runs on the CPU.
ENGINES = ["CYCLES", "BLENDER_EEVEE"]


@pytest.mark.parametrize("engine", ENGINES)
def test_blender_renders_the_gltf_copy_at_the_maps_brightness(gltf_bake, tmp_path, engine):
    import bpy

    out, _ = gltf_bake
    copy = json.loads((out / "head.gltf").read_text())
    strength = baked_material(copy)["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=str(out / "head.gltf"))
    material = bpy.data.objects["Head"].active_material
    assert material.name == "Head (sssbake)"
    surface = principled(material)
    # Blender's importer carries the strength to the Principled BSDF (it would be 1 without).
    assert surface.inputs["Emission Strength"].default_value == pytest.approx(strength, rel=1e-5)
    assert tuple(surface.inputs["Base Color"].default_value)[:3] == (0, 0, 0)
    images = [n.image for n in material.node_tree.nodes if n.type == "TEX_IMAGE"]
    assert [pathlib.Path(i.filepath).name for i in images] == ["Head_diffuse_emissive.png"]
    rendered = render_flat(bpy, material, uv_map_name(material), tmp_path / "gltf.exr", engine)
    diffuse = exr(out / "Head_diffuse.exr").astype(np.float64)
    # 8-bit sRGB: half a step is 1.6% at a twentieth of the maximum, less above.
    assert_renders_the_map(rendered, as_rendered(diffuse, engine), 0.03)


@pytest.mark.parametrize("engine", ENGINES)
def test_blender_renders_the_usd_layer_at_the_maps_brightness(usd_bake, tmp_path, engine):
    import bpy

    out, _ = usd_bake
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.usd_import(filepath=str(out / "head_sssbake.usda"))
    head = next(o for o in bpy.data.objects if o.type == "MESH")
    material = head.active_material
    assert material.name == "Head"
    images = [n.image for n in material.node_tree.nodes if n.type == "TEX_IMAGE"]
    assert [pathlib.Path(i.filepath).name for i in images] == ["Head_diffuse.exr"]
    assert images[0].colorspace_settings.name == "Non-Color"
    surface = principled(material)
    assert surface.inputs["Emission Color"].is_linked
    assert tuple(surface.inputs["Base Color"].default_value)[:3] == (0, 0, 0)
    rendered = render_flat(bpy, material, uv_map_name(material), tmp_path / "usd.exr", engine)
    diffuse = exr(out / "Head_diffuse.exr").astype(np.float64)
    assert_renders_the_map(rendered, as_rendered(diffuse, engine), 0.01)


# (d) The imported head from a camera, as a person looks at it in Blender.

VIEW_SIZE = 320


def aim_camera(bpy, target, direction, distance: float):
    """A 30° perspective camera `distance` from `target`, looking back along `direction`."""
    from mathutils import Vector

    scene = bpy.context.scene
    camera = bpy.data.objects.new("View", bpy.data.cameras.new("View"))
    camera.data.angle = math.radians(30)
    camera.location = Vector(target) + Vector(direction).normalized() * distance
    camera.rotation_euler = (Vector(target) - camera.location).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(camera)
    scene.camera = camera


def texture_coordinates(bpy, mesh_object, uv_name: str, path: pathlib.Path) -> tuple[np.ndarray, np.ndarray]:
    """Each pixel's texture coordinates (origin at the image's top left) and whether the
    object covers it, from the same camera, every material showing its UVs as emission."""
    material = bpy.data.materials.new("Coordinates")
    nodes = material.node_tree.nodes
    nodes.clear()
    coordinates = nodes.new("ShaderNodeUVMap")
    coordinates.uv_map = uv_name
    emission = nodes.new("ShaderNodeEmission")
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(coordinates.outputs["UV"], emission.inputs["Color"])
    material.node_tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
    for slot in mesh_object.material_slots:
        slot.link = "OBJECT"
        slot.material = material
    pixels = render_view(bpy, "CYCLES", path, VIEW_SIZE)
    uv = np.stack([pixels[..., 0], 1.0 - pixels[..., 1]], axis=-1)
    return uv, pixels[..., 3] > 0.999


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("asset", ["gltf", "usd"])
def test_blender_shows_the_imported_head_at_the_maps_radiance(gltf_bake, usd_bake, tmp_path, engine, asset):
    """The glTF copy or the USD layer imported with its lights, seen from a camera: every
    pixel where the map is smooth shows the map's radiance, nothing added by the lights."""
    import bpy

    out, _ = gltf_bake if asset == "gltf" else usd_bake
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if asset == "gltf":
        bpy.ops.import_scene.gltf(filepath=str(out / "head.gltf"))
    else:
        bpy.ops.wm.usd_import(filepath=str(out / "head_sssbake.usda"))
    scene = bpy.context.scene
    assert [o for o in scene.objects if o.type == "LIGHT"], "the asset's lights are in the scene"
    (head,) = [o for o in scene.objects if o.type == "MESH"]
    from mathutils import Vector

    corners = np.array([head.matrix_world @ Vector(c) for c in head.bound_box])
    centre, size = corners.mean(axis=0), float(np.linalg.norm(corners.max(axis=0) - corners.min(axis=0)))
    # From above and behind, where the key light falls (the web check's view of the head).
    aim_camera(bpy, centre, (0.0, 0.84, 0.54), 1.2 * size)
    look = render_view(bpy, engine, tmp_path / "look.exr", VIEW_SIZE)
    uv, covered = texture_coordinates(bpy, head, uv_map_name(head.active_material), tmp_path / "uv.exr")

    diffuse = exr(out / "Head_diffuse.exr").astype(np.float64)
    expected = radiance_at(diffuse, uv, covered)
    chosen = smooth_pixels(expected, covered, uv, diffuse) & (expected > 0.2 * diffuse.max())
    shown = assert_shows(look[..., :3], expected, chosen)
    print(f"{engine} shows the {asset} import: {shown}")
    assert nothing_outside(look[..., :3], covered)
