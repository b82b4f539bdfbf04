"""Every example baked through the CLI: the maps are physical, the glTF copy passes the
Khronos validator and imports into Blender with the bake on the right object."""

import json
import pathlib
import subprocess

import numpy as np
import pytest
from conftest import ROOT, exr, run

EXAMPLES = {"head": "Head", "marble": "Ball", "ear": "Ear"}


@pytest.fixture(scope="module")
def baked(sssbake, tmp_path_factory):
    results = {}
    for name in EXAMPLES:
        out = tmp_path_factory.mktemp(name)
        result = run(
            sssbake,
            "bake",
            str(ROOT / "examples" / name / f"{name}.gltf"),
            "--out",
            str(out),
            "--resolution",
            "128",
            "--outputs",
            "subsurface,irradiance,diffuse,area",
            "--force",
            "--json",
        )
        assert result.returncode == 0, result.stderr
        results[name] = (out, json.loads(result.stdout))
    return results


@pytest.mark.parametrize("name", EXAMPLES)
def test_maps_are_finite_and_create_no_light(baked, name):
    out, summary = baked[name]
    obj = EXAMPLES[name]
    assert summary["objects"][0]["name"] == obj
    subsurface, irradiance, area = (exr(out / f"{obj}_{o}.exr") for o in ("subsurface", "irradiance", "area"))
    assert subsurface.shape == (128, 128, 3)
    assert np.isfinite(subsurface).all() and (subsurface >= 0).all()
    flux_in = (irradiance * area).sum()
    flux_out = (subsurface * area).sum()
    assert flux_in > 0
    assert 0.1 * flux_in < flux_out <= flux_in


@pytest.mark.parametrize("name", EXAMPLES)
def test_the_gltf_copy_passes_the_khronos_validator(baked, name):
    out, _ = baked[name]
    validator = ROOT / ".node" / "node_modules" / "gltf-validator"
    assert validator.exists(), "scripts/install-test-deps.sh installs the validator"
    result = subprocess.run(
        ["node", str(ROOT / "tests" / "validate_gltf.js"), str(out / f"{name}.gltf")],
        capture_output=True,
        text=True,
        check=False,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    issues = json.loads(result.stdout)["issues"]
    assert issues["numErrors"] == 0, issues["messages"]


def test_the_gltf_copy_imports_into_blender_with_the_bake(baked):
    import bpy

    out, _ = baked["marble"]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=str(out / "marble.gltf"))
    ball = bpy.data.objects["Ball"]
    material = ball.active_material
    assert material.name == "Ball (sssbake)"
    images = [n.image for n in material.node_tree.nodes if n.type == "TEX_IMAGE"]
    assert [pathlib.Path(i.filepath).name for i in images] == ["Ball_diffuse_emissive.png"]
    assert tuple(images[0].size) == (128, 128)
