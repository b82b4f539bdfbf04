"""One Blender scene exported by bpy to glTF and to USD reads the same in sssbake."""

import json
import sys

import pytest
from conftest import run


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    import bpy

    folder = tmp_path_factory.mktemp("scene")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_monkey_add(location=(0, 0, 0))
    suzanne = bpy.context.active_object
    suzanne.name = "Suzanne"
    suzanne.modifiers.new("smooth", "SUBSURF").levels = 1
    bpy.ops.object.modifier_apply(modifier="smooth")
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(3, 0, 0))
    bpy.context.active_object.name = "Ball"
    bpy.ops.mesh.primitive_cube_add(size=0.2, location=(0, 3, 0))
    bpy.context.active_object.name = "Box"
    bpy.ops.object.light_add(type="SUN", location=(0, 0, 5))
    gltf = folder / "scene.glb"
    usd = folder / "scene.usda"
    bpy.ops.export_scene.gltf(filepath=str(gltf), export_lights=True)
    bpy.ops.wm.usd_export(filepath=str(usd))
    return gltf, usd


def plan(sssbake, path):
    result = run(
        sssbake, "plan", str(path), "--json", "--resolution", "512", env={"SSSBAKE_PYTHON": sys.executable}
    )
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def test_gltf_and_usd_exports_read_the_same(sssbake, exported):
    gltf, usd = exported
    from_gltf, from_usd = plan(sssbake, gltf), plan(sssbake, usd)
    assert from_gltf["millimetres_per_unit"] == from_usd["millimetres_per_unit"] == 1000.0
    objects = {o["name"]: o for o in from_gltf["objects"]}
    assert set(objects) == {"Suzanne", "Ball", "Box"}
    for other in from_usd["objects"]:
        mine = objects[other["name"]]
        assert mine["triangles"] == other["triangles"]
        # Non-planar quads split along either diagonal differ a little.
        assert mine["area_mm2"] == pytest.approx(other["area_mm2"], rel=1e-3)
        # Both readers put v up, so the same UVs cover the same texels.
        assert mine["texels"] == other["texels"]
        assert mine["uvs"]["unwrap"] == other["uvs"]["unwrap"]
    box = objects["Box"]
    assert box["area_mm2"] == pytest.approx(6 * 200.0**2, rel=1e-6)
    assert len(from_gltf["lights"]) == len(from_usd["lights"]) == 1


def test_usd_without_usd_core_says_what_it_needs(sssbake, exported, tmp_path):
    _, usd = exported
    fake = tmp_path / "python"
    fake.write_text("#!/bin/sh\necho 'ModuleNotFoundError: No module named pxr' >&2\nexit 1\n")
    fake.chmod(0o755)
    result = run(sssbake, "plan", str(usd), env={"SSSBAKE_PYTHON": str(fake)})
    assert result.returncode == 1
    assert str(usd) in result.stderr and "usd-core could not read it" in result.stderr
