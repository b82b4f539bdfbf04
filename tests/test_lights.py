"""Lights through the doors that carry them: the add-on reads a Blender light's exposure,
temperature, diffuse factor, normalization, spread and shadow flag, and bakes and shadows
with what renders (not what the viewport shows); a UsdLux colour temperature bakes as
usd-core's own blackbody colour."""

import numpy as np
import pytest
from conftest import bake_summary, exr


def test_a_blender_light_carries_what_cycles_reads(addon):
    import bpy

    scene_export = addon.scene_export

    data = bpy.data.lights.new("Area", "AREA")
    data.energy, data.exposure, data.diffuse_factor = 10.0, 1.5, 0.25
    data.use_temperature, data.temperature = True, 3000.0
    data.normalize, data.use_shadow, data.spread = False, False, 1.0
    obj = bpy.data.objects.new("Area", data)
    bpy.context.scene.collection.objects.link(obj)
    light = scene_export.light_fields(obj)
    assert light["kind"] == "rectangle"
    assert light["exposure"] == pytest.approx(1.5) and light["diffuse_factor"] == pytest.approx(0.25)
    assert tuple(light["temperature_colour"]) == pytest.approx(tuple(data.temperature_color))
    assert (light["normalize"], light["casts_shadow"]) == (False, False)
    assert light["spread"] == pytest.approx(1.0)
    # Without use_temperature the colour is the light's own.
    data.use_temperature = False
    assert tuple(scene_export.light_fields(obj)["temperature_colour"]) == (1.0, 1.0, 1.0)
    # A light that reaches no diffuse rays lights no subsurface.
    obj.visible_diffuse = False
    assert scene_export.light_fields(obj) is None


def floor_under_a_blocker():
    """A 1 m floor (selected) under a sun straight down, half of it under a blocker."""
    import bpy

    bpy.ops.mesh.primitive_plane_add(size=1.0)
    floor = bpy.context.active_object
    floor.name = "Floor"
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0.5, 0.0, 0.3))
    blocker = bpy.context.active_object
    blocker.name = "Blocker"
    bpy.ops.object.light_add(type="SUN", rotation=(0.0, 0.0, 0.0))
    sun = bpy.context.active_object
    sun.data.energy, sun.data.angle = 2.0, 0.0
    bpy.ops.object.select_all(action="DESELECT")
    floor.select_set(True)
    bpy.context.view_layer.objects.active = floor
    return blocker, sun


def shadowed_share():
    """The share of the floor's covered texels in shadow after a bake of its irradiance."""
    import bpy

    assert bpy.ops.sssbake.bake(preset="skin1", resolution=32, outputs={"IRRADIANCE"}) == {"FINISHED"}
    image = bpy.data.images["Floor_irradiance"]
    values = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(values)
    texels = values.reshape(-1, 4)
    covered = texels[texels[:, 3] > 0][:, 0]
    return float((covered < 0.5 * covered.max()).mean())


def test_what_renders_casts_shadows_whatever_the_viewport_shows(addon):
    import bpy

    blocker, sun = floor_under_a_blocker()
    assert shadowed_share() == pytest.approx(0.5, abs=0.1)
    # Hidden in the viewport only: it still renders, so it still shadows.
    blocker.hide_set(True)
    assert shadowed_share() == pytest.approx(0.5, abs=0.1)
    blocker.hide_set(False)
    # Hidden from renders, or in a collection hidden from renders: no shadow.
    blocker.hide_render = True
    assert shadowed_share() == 0.0
    blocker.hide_render = False
    hidden = bpy.data.collections.new("Hidden")
    bpy.context.scene.collection.children.link(hidden)
    hidden.objects.link(blocker)
    bpy.context.scene.collection.objects.unlink(blocker)
    hidden.hide_render = True
    assert shadowed_share() == 0.0
    hidden.hide_render = False
    assert shadowed_share() == pytest.approx(0.5, abs=0.1)
    # A sun that casts no shadows.
    sun.data.use_shadow = False
    assert shadowed_share() == 0.0


def test_an_object_hidden_from_renders_is_not_baked(addon, capfd):
    import bpy

    floor_under_a_blocker()
    bpy.data.objects["Floor"].hide_render = True
    result = bpy.ops.sssbake.bake(preset="skin1", resolution=16, outputs={"IRRADIANCE"})
    assert result == {"CANCELLED"}
    assert "hidden from renders" in capfd.readouterr().out
    assert "Floor_irradiance" not in bpy.data.images


def test_a_usd_colour_temperature_bakes_as_usd_cores_blackbody(sssbake, tmp_path):
    from pxr import Sdf, Usd, UsdGeom, UsdLux

    stage_path = tmp_path / "warm.usda"
    stage = Usd.Stage.CreateNew(str(stage_path))
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    plane = UsdGeom.Mesh.Define(stage, "/Plane")
    plane.CreatePointsAttr([(-0.5, -0.5, 0), (0.5, -0.5, 0), (0.5, 0.5, 0), (-0.5, 0.5, 0)])
    plane.CreateFaceVertexCountsAttr([4])
    plane.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    st = UsdGeom.PrimvarsAPI(plane).CreatePrimvar(
        "st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.faceVarying
    )
    st.Set([(0, 0), (1, 0), (1, 1), (0, 1)])
    light = UsdLux.SphereLight.Define(stage, "/Warm")
    light.CreateRadiusAttr(0.0)
    light.CreateIntensityAttr(100.0)
    light.CreateEnableColorTemperatureAttr(True)
    light.CreateColorTemperatureAttr(3000.0)
    UsdGeom.XformCommonAPI(light).SetTranslate((0.0, 0.0, 1.0))
    stage.GetRootLayer().Save()
    bake_summary(sssbake, stage_path, tmp_path / "out", "--outputs", "irradiance", "--resolution", "16")
    texels = exr(tmp_path / "out" / "Plane_irradiance.exr").reshape(-1, 3)
    lit = texels[texels[:, 1] > 0]
    want = np.array(UsdLux.BlackbodyTemperatureAsRgb(3000.0))
    ratio = lit / lit[:, 1:2]
    assert np.allclose(ratio, want / want[1], rtol=0.02), (ratio[0], want / want[1])
