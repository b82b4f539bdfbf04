"""Base-colour textures read from glTF and USD and counted once: a two-colour texture
bakes two different halves, a constant texture bakes what the same colour as a factor
bakes, and an image that cannot be read stops the bake naming the file and the
material, leaving no output."""

import base64
import json
import struct
import sys
import zlib

import numpy as np
import pytest
from conftest import exr, run, srgb_to_linear

LEFT, RIGHT = (200, 90, 60), (70, 160, 190)


def png(path, rows):
    """Writes 8-bit RGB `rows` (top to bottom, lists of (r, g, b) codes) as a PNG."""

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    height, width = len(rows), len(rows[0])
    raw = b"".join(b"\x00" + bytes(v for texel in row for v in texel) for row in rows)
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    path.write_bytes(
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", header)
        + chunk(b"IDAT", zlib.compress(raw))
        + chunk(b"IEND", b"")
    )
    return path


def plane_gltf(folder, factor, image=None, name="plane.gltf"):
    """A 60 mm square facing +Y under a 1 W/m² sun, its material a glTF volume of mean
    free path 1 mm / ln 2 with base colour `factor` and, when `image` names a file, that
    image as baseColorTexture (nearest, clamped)."""
    h = 0.03
    positions = [(-h, 0, h), (h, 0, h), (h, 0, -h), (-h, 0, -h)]
    normals = [(0, 1, 0)] * 4
    uvs = [(0, 1), (1, 1), (1, 0), (0, 0)]
    indices = [0, 1, 2, 0, 2, 3]
    blob = (
        b"".join(struct.pack("<3f", *p) for p in positions)
        + b"".join(struct.pack("<3f", *n) for n in normals)
        + b"".join(struct.pack("<2f", *t) for t in uvs)
        + struct.pack("<6H", *indices)
    )
    material = {
        "name": "Skin",
        "pbrMetallicRoughness": {"baseColorFactor": [*factor, 1.0]},
        "extensions": {
            "KHR_materials_volume": {"attenuationDistance": 0.001, "attenuationColor": [0.5, 0.5, 0.5]},
            "KHR_materials_ior": {"ior": 1.4},
        },
    }
    document = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_volume", "KHR_materials_ior", "KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 683.0}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"name": "Plane", "mesh": 0},
            {
                "name": "Sun",
                "rotation": [-0.7071068, 0, 0, 0.7071068],
                "extensions": {"KHR_lights_punctual": {"light": 0}},
            },
        ],
        "meshes": [
            {
                "primitives": [
                    {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}
                ]
            }
        ],
        "materials": [material],
        "buffers": [
            {
                "byteLength": len(blob),
                "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode(),
            }
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 32},
            {"buffer": 0, "byteOffset": 128, "byteLength": 12},
        ],
        "accessors": [
            {
                "bufferView": 0,
                "componentType": 5126,
                "count": 4,
                "type": "VEC3",
                "min": [-h, 0, -h],
                "max": [h, 0, h],
            },
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
    }
    if image is not None:
        material["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
        document["textures"] = [{"source": 0, "sampler": 0}]
        document["samplers"] = [{"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33071}]
        document["images"] = [{"uri": image}]
    path = folder / name
    path.write_text(json.dumps(document))
    return path


def bake(sssbake, scene, out, *extra, python=False):
    result = run(
        sssbake,
        "bake",
        str(scene),
        "--out",
        str(out),
        "--resolution",
        "32",
        "--outputs",
        "subsurface",
        "--json",
        *extra,
        env={"SSSBAKE_PYTHON": sys.executable} if python else None,
    )
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def halves(subsurface):
    """Mean of the left and the right quarter-columns (away from the edge), rows 8..24."""
    return subsurface[8:24, 2:12].mean(axis=(0, 1)), subsurface[8:24, 20:30].mean(axis=(0, 1))


def test_a_two_colour_gltf_texture_bakes_two_halves(sssbake, tmp_path):
    png(tmp_path / "two.png", [[LEFT, RIGHT]])
    scene = plane_gltf(tmp_path, (1.0, 1.0, 1.0), "two.png")
    summary = bake(sssbake, scene, tmp_path / "out")
    colour = summary["objects"][0]["colour"]
    assert colour["source"] == "texture"
    assert colour["file"].endswith("two.png")
    assert colour["uv_set"] == "TEXCOORD_0"
    assert colour["colour_space"] == "sRGB"
    left, right = srgb_to_linear(np.array(LEFT) / 255), srgb_to_linear(np.array(RIGHT) / 255)
    assert np.allclose(colour["nominal"], (left + right) / 2, rtol=1e-3)
    a, b = halves(exr(tmp_path / "out" / "Plane_subsurface.exr"))
    assert np.allclose(a / b, left / right, rtol=0.1), (a / b, left / right)


def test_a_constant_gltf_texture_bakes_what_the_factor_bakes(sssbake, tmp_path):
    code = (200, 120, 90)
    png(tmp_path / "flat.png", [[code] * 4] * 4)
    textured = plane_gltf(tmp_path, (1.0, 1.0, 1.0), "flat.png", "textured.gltf")
    factor = plane_gltf(tmp_path, tuple(srgb_to_linear(np.array(code) / 255)), None, "factor.gltf")
    bake(sssbake, textured, tmp_path / "t")
    summary = bake(sssbake, factor, tmp_path / "f")
    assert summary["objects"][0]["colour"]["source"] == "material"
    t, f = exr(tmp_path / "t" / "Plane_subsurface.exr"), exr(tmp_path / "f" / "Plane_subsurface.exr")
    assert f.max() > 0
    assert np.allclose(t, f, rtol=1e-5, atol=1e-12 * f.max()), np.abs(t / np.maximum(f, 1e-30) - 1).max()


@pytest.mark.parametrize("bad", ["missing", "truncated"])
def test_an_image_that_cannot_be_read_stops_the_bake(sssbake, tmp_path, bad):
    if bad == "truncated":
        whole = png(tmp_path / "bad.png", [[LEFT, RIGHT]] * 8).read_bytes()
        (tmp_path / "bad.png").write_bytes(whole[: len(whole) // 2])
    scene = plane_gltf(tmp_path, (1.0, 1.0, 1.0), "bad.png")
    out = tmp_path / "out"
    result = run(sssbake, "bake", str(scene), "--out", str(out), "--resolution", "16")
    assert result.returncode == 1, result.stderr
    for word in ["bad.png", "`Skin`", "baseColorTexture", "Plane"]:
        assert word in result.stderr, result.stderr
    assert not out.exists()


def usd_plane(folder, shader_id, colour_input, image=None, colour=(0.8, 0.5, 0.4), name="plane.usda"):
    """The glTF plane's twin in USD (mm, Y up) with `shader_id` whose `colour_input` is
    `colour`, or an sRGB UsdUVTexture of `image` (clamped) when one is given."""
    from pxr import Gf, Sdf, Usd, UsdGeom, UsdLux, UsdShade

    stage = Usd.Stage.CreateNew(str(folder / name))
    UsdGeom.SetStageMetersPerUnit(stage, 0.001)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    root = UsdGeom.Xform.Define(stage, "/root")
    stage.SetDefaultPrim(root.GetPrim())
    UsdGeom.Xform.Define(stage, "/root/Plane")
    mesh = UsdGeom.Mesh.Define(stage, "/root/Plane/Mesh")
    mesh.CreatePointsAttr([(-30, 0, 30), (30, 0, 30), (30, 0, -30), (-30, 0, -30)])
    mesh.CreateFaceVertexCountsAttr([4])
    mesh.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    st = UsdGeom.PrimvarsAPI(mesh).CreatePrimvar(
        "st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.vertex
    )
    st.Set([(0, 0), (1, 0), (1, 1), (0, 1)])
    sun = UsdLux.DistantLight.Define(stage, "/root/Sun")
    sun.CreateIntensityAttr(1.0)
    sun.CreateAngleAttr(0.0)
    UsdGeom.Xformable(sun).AddRotateXOp().Set(-90.0)
    material = UsdShade.Material.Define(stage, "/root/Looks/Skin")
    shader = UsdShade.Shader.Define(stage, "/root/Looks/Skin/Surface")
    shader.CreateIdAttr(shader_id)
    if shader_id == "UsdPreviewSurface":
        shader.CreateInput("ior", Sdf.ValueTypeNames.Float).Set(1.4)
        material.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    else:
        for key, kind, value in [
            ("subsurface_weight", Sdf.ValueTypeNames.Float, 1.0),
            ("subsurface_radius", Sdf.ValueTypeNames.Float, 1.0),
            ("subsurface_radius_scale", Sdf.ValueTypeNames.Color3f, Gf.Vec3f(1.0, 0.5, 0.25)),
            ("specular_ior", Sdf.ValueTypeNames.Float, 1.4),
        ]:
            shader.CreateInput(key, kind).Set(value)
        material.CreateSurfaceOutput("mtlx").ConnectToSource(shader.ConnectableAPI(), "out")
    target = shader.CreateInput(colour_input, Sdf.ValueTypeNames.Color3f)
    if image is None:
        target.Set(Gf.Vec3f(*colour))
    else:
        reader = UsdShade.Shader.Define(stage, "/root/Looks/Skin/St")
        reader.CreateIdAttr("UsdPrimvarReader_float2")
        reader.CreateInput("varname", Sdf.ValueTypeNames.String).Set("st")
        texture = UsdShade.Shader.Define(stage, "/root/Looks/Skin/Texture")
        texture.CreateIdAttr("UsdUVTexture")
        texture.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(image)
        texture.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set("sRGB")
        texture.CreateInput("wrapS", Sdf.ValueTypeNames.Token).Set("clamp")
        texture.CreateInput("wrapT", Sdf.ValueTypeNames.Token).Set("clamp")
        texture.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(
            reader.ConnectableAPI(), "result"
        )
        target.ConnectToSource(texture.ConnectableAPI(), "rgb")
    UsdShade.MaterialBindingAPI.Apply(mesh.GetPrim()).Bind(material)
    stage.Save()
    return folder / name


@pytest.mark.parametrize(
    "shader_id,colour_input",
    [("ND_open_pbr_surface_surfaceshader", "subsurface_color"), ("UsdPreviewSurface", "diffuseColor")],
)
def test_a_usd_texture_is_read_and_counted_once(sssbake, tmp_path, shader_id, colour_input):
    # UsdUVTexture filters bilinearly: 16 texels a side keep the halves flat.
    png(tmp_path / "two.png", [[LEFT] * 16 + [RIGHT] * 16] * 2)
    two = usd_plane(tmp_path, shader_id, colour_input, "two.png", name="two.usda")
    summary = bake(sssbake, two, tmp_path / "two", python=True)
    colour = summary["objects"][0]["colour"]
    assert colour["source"] == "texture", summary
    assert colour["input"] == colour_input
    assert colour["uv_set"] == "primvar `st`"
    assert not any(colour_input in note for note in summary["notes"]), summary["notes"]
    left, right = srgb_to_linear(np.array(LEFT) / 255), srgb_to_linear(np.array(RIGHT) / 255)
    a, b = halves(exr(tmp_path / "two" / "Plane_subsurface.exr"))
    # The preview surface takes skin1's scattering distance, a reach of a few mm in red.
    assert np.allclose(a / b, left / right, rtol=0.15), (a / b, left / right)

    code = (200, 120, 90)
    png(tmp_path / "flat.png", [[code] * 4] * 4)
    flat = usd_plane(tmp_path, shader_id, colour_input, "flat.png", name="flat.usda")
    plain = usd_plane(
        tmp_path,
        shader_id,
        colour_input,
        colour=tuple(srgb_to_linear(np.array(code) / 255)),
        name="plain.usda",
    )
    bake(sssbake, flat, tmp_path / "flat", python=True)
    bake(sssbake, plain, tmp_path / "plain", python=True)
    t, f = exr(tmp_path / "flat" / "Plane_subsurface.exr"), exr(tmp_path / "plain" / "Plane_subsurface.exr")
    assert f.max() > 0
    assert np.allclose(t, f, rtol=1e-5, atol=1e-12 * f.max())
