"""A USD input baked through the CLI: the layer over it composes, binds the bake on the
right prim, passes usd-core's validators, packages as .usdz and imports into Blender."""

import sys

import pytest
from conftest import ROOT, run, usd_validation_errors


@pytest.fixture(scope="module")
def layer(sssbake, tmp_path_factory):
    out = tmp_path_factory.mktemp("usd")
    result = run(
        sssbake,
        "bake",
        str(ROOT / "examples" / "marble" / "marble.usda"),
        "--out",
        str(out),
        "--resolution",
        "64",
        env={"SSSBAKE_PYTHON": sys.executable},
    )
    assert result.returncode == 0, result.stderr
    return out / "marble_sssbake.usda"


def test_the_layer_binds_the_diffuse_map_to_the_baked_mesh(layer):
    from pxr import Usd, UsdShade

    stage = Usd.Stage.Open(str(layer))
    meshes = [p for p in stage.Traverse() if p.GetTypeName() == "Mesh"]
    assert len(meshes) == 1
    material, _ = UsdShade.MaterialBindingAPI(meshes[0]).ComputeBoundMaterial()
    assert material.GetPrim().GetName() == "Ball"
    assert material.GetPrim().GetAttribute("sssbake:method").Get() == "brute"
    texture = UsdShade.Shader(material.GetPrim().GetChild("emission"))
    assert texture.GetInput("file").Get().path == "Ball_diffuse.exr"
    assert (layer.parent / "Ball_diffuse.exr").exists()
    # The input stage is only sublayered, never written.
    assert "sssbake" not in (ROOT / "examples" / "marble" / "marble.usda").read_text()


def test_the_layer_passes_validation_and_packages(layer, tmp_path):
    from pxr import Usd, UsdUtils

    assert usd_validation_errors(Usd.Stage.Open(str(layer))) == []
    package = tmp_path / "marble.usdz"
    assert UsdUtils.CreateNewUsdzPackage(str(layer), str(package))
    assert package.stat().st_size > 0


def test_the_layer_imports_into_blender_with_the_bake(layer):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.usd_import(filepath=str(layer))
    ball = next(o for o in bpy.data.objects if o.type == "MESH")
    images = [n.image for n in ball.active_material.node_tree.nodes if n.type == "TEX_IMAGE"]
    assert [i.name for i in images] == ["Ball_diffuse.exr"]
    assert tuple(images[0].size) == (64, 64)
