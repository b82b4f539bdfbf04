"""The Blender add-on in a headless bpy: registered from blender_addon/, it bakes Suzanne
on a floor under a sun into images, agrees texel for texel with the CLI baking the same
scene exported to glTF, leaves the scene as it was when cancelled, answers bad settings
with a report, and packages as an extension with its licenses that Blender's check accepts."""

import json
import os
import pathlib
import subprocess
import sys
import threading
import zipfile

import numpy as np
import OpenEXR
import pytest
from conftest import ROOT, run
from skin_material import principled_skin


def suzanne_scene():
    """Suzanne (subdivided once) in a Principled skin, a floor, a hard sun; Suzanne selected."""
    import bpy

    bpy.ops.mesh.primitive_monkey_add(size=0.2)
    head = bpy.context.active_object
    head.name = "Head"
    head.modifiers.new("smooth", "SUBSURF").levels = 1
    bpy.ops.object.shade_smooth()
    head.data.materials.append(principled_skin(0.002))
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0.0, 0.0, -0.12))
    bpy.context.active_object.name = "Floor"
    bpy.ops.object.light_add(type="SUN", rotation=(0.6, 0.3, 0.0))
    sun = bpy.context.active_object
    sun.data.energy = 2.0
    sun.data.angle = 0.0
    bpy.ops.object.select_all(action="DESELECT")
    head.select_set(True)
    bpy.context.view_layer.objects.active = head
    return head


def pixels(name):
    import bpy

    image = bpy.data.images[name]
    values = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(values)
    return values.reshape(image.size[1], image.size[0], 4)


def test_the_operator_makes_images_with_physical_values(addon):
    import bpy

    suzanne_scene()
    result = bpy.ops.sssbake.bake(resolution=64, method="BRUTE", outputs={"SUBSURFACE", "IRRADIANCE", "AREA"})
    assert result == {"FINISHED"}
    subsurface, irradiance, area = (pixels(f"Head_{o}") for o in ("subsurface", "irradiance", "area"))
    assert subsurface.shape == (64, 64, 4)
    assert np.isfinite(subsurface).all() and (subsurface >= 0).all()
    covered = area[..., 3] > 0
    flux_in = (irradiance[..., :3].sum(axis=2) * area[..., 0])[covered].sum()
    flux_out = (subsurface[..., :3].sum(axis=2) * area[..., 0])[covered].sum()
    assert flux_in > 0 and 0.2 * flux_in < flux_out < flux_in
    # Skin: red travels furthest and leaves most.
    mean = subsurface[covered][:, :3].mean(axis=0)
    assert mean[0] > mean[1] > mean[2]
    assert bpy.data.images["Head_subsurface"].packed_file is not None


def exr(path):
    return OpenEXR.File(str(path)).parts[0].channels["RGB"].pixels


def test_the_cli_bakes_the_same_scene_from_gltf_to_the_same_texels(addon, sssbake, tmp_path):
    import bpy

    head = suzanne_scene()
    # A point light and a spot with hard edges, as glTF carries them.
    for kind, location, power in (("POINT", (0.15, -0.2, 0.1), 30.0), ("SPOT", (-0.2, -0.25, 0.2), 60.0)):
        bpy.ops.object.light_add(type=kind, location=location, rotation=(1.0, 0.0, -0.6))
        light = bpy.context.active_object.data
        light.energy, light.shadow_soft_size = power, 0.0
        if kind == "SPOT":
            light.spot_size, light.spot_blend = 1.2, 0.0
    bpy.ops.object.select_all(action="DESELECT")
    head.select_set(True)
    common = {"resolution": 64, "method": "BRUTE", "margin": 0}
    # A preset given alone picks the preset as the material.
    result = bpy.ops.sssbake.bake(preset="skin1", outputs={"SUBSURFACE", "IRRADIANCE"}, **common)
    assert result == {"FINISHED"}
    scene = tmp_path / "suzanne.gltf"
    bpy.ops.export_scene.gltf(
        filepath=str(scene), export_format="GLTF_SEPARATE", export_lights=True, export_apply=True
    )
    baked = run(
        sssbake,
        "bake",
        str(scene),
        "--object",
        "Head",
        "--out",
        str(tmp_path / "cli"),
        "--preset",
        "skin1",
        "--resolution",
        "64",
        "--method",
        "brute",
        "--margin",
        "0",
        "--light-samples",
        "16",
        "--outputs",
        "subsurface,irradiance",
    )
    assert baked.returncode == 0, baked.stderr
    for output in ("irradiance", "subsurface"):
        blender = pixels(f"Head_{output}")
        covered = blender[..., 3] > 0
        # The CLI's rows run down the image; Blender's run up.
        cli = exr(tmp_path / "cli" / f"Head_{output}.exr")[::-1]
        assert covered.sum() > 1000
        scale = np.abs(cli[covered]).max()
        difference = np.abs(cli[covered] - blender[..., :3][covered]).max()
        assert difference <= 1e-3 * scale, (output, difference, scale)


def test_a_cancelled_bake_leaves_the_scene_unchanged(addon, capfd):
    import bpy

    head = suzanne_scene()
    nodes_before = sorted(n.name for n in head.active_material.node_tree.nodes)
    maps_before = [layer.name for layer in head.data.uv_layers]
    active_before = head.data.uv_layers.active.name
    finished = threading.Event()

    def keep_cancelling():
        while not finished.wait(0.05):
            addon.operators.cancel_running()

    canceller = threading.Thread(target=keep_cancelling)
    canceller.start()
    try:
        result = bpy.ops.sssbake.bake(resolution=2048, method="BRUTE", unwrap=True, wire_material=True)
    finally:
        finished.set()
        canceller.join()
    assert result == {"CANCELLED"}
    assert "sssbake: cancelled; nothing was changed" in capfd.readouterr().out
    assert len(bpy.data.images) == 0
    assert [layer.name for layer in head.data.uv_layers] == maps_before
    assert head.data.uv_layers.active.name == active_before
    assert sorted(n.name for n in head.active_material.node_tree.nodes) == nodes_before


def test_bad_settings_give_a_report_not_an_exception(addon, tmp_path, capfd):
    import bpy

    head = suzanne_scene()
    cases = [
        ({"uv_map": "NoSuchMap"}, "has no UV map `NoSuchMap`; choose one, or tick Unwrap"),
        (
            {"material_source": "LAYERS", "layers_file": str(tmp_path / "missing.toml")},
            "cannot read the layers file",
        ),
        ({"destination": "FOLDER", "folder": ""}, "choose a folder"),
        ({"outputs": set()}, "choose at least one output"),
        # Below what any bake holds: refused by the library's plan, naming the limit.
        ({"max_memory": 0.001}, "max_memory: the bake would hold about"),
        ({"max_memory": 0.001}, "over the limit of 1.0 MiB"),
        ({"max_memory": 0.001}, "raise the limit (the Memory Limit (GiB) of the sssbake panel)"),
    ]
    for settings, message in cases:
        assert bpy.ops.sssbake.bake(resolution=16, **settings) == {"CANCELLED"}
        assert message in capfd.readouterr().out, settings
    head.active_material.node_tree.nodes["Principled BSDF"].inputs["Subsurface Weight"].default_value = 0.0
    assert bpy.ops.sssbake.bake(resolution=16) == {"CANCELLED"}
    assert "Subsurface Weight is 0" in capfd.readouterr().out
    # With nothing selected the operator is not offered (its poll() says why).
    bpy.ops.object.select_all(action="DESELECT")
    assert not bpy.ops.sssbake.bake.poll()
    assert len(bpy.data.images) == 0


def test_every_setting_of_a_bake_is_in_the_panel_with_the_librarys_default(addon):
    """A setting the library adds appears in the panel by itself: each setting of a bake or
    an integrator is a property (under Advanced) with the library's doc, default and range,
    unless the panel shows it in its own terms; and what the panel holds is what the bake
    gets, in the library's terms."""
    import bpy
    import sssbake

    panel = bpy.context.scene.sssbake
    rna = panel.bl_rna.properties
    offered = 0
    for setting in sssbake.settings():
        if setting["part"] in ("scene", "writing") or setting["default"] is None:
            continue
        if setting["name"] in addon.properties.OWN_TERMS:
            continue
        offered += 1
        name = setting["name"]
        assert setting["doc"].rstrip(".") in rna[name].description, name
        value = getattr(panel, name)
        assert value == pytest.approx(setting["default"], rel=1e-6), name
        if setting["kind"] == "count":
            assert rna[name].hard_min == setting["min"], name
    assert offered >= 8 and set(addon.panels.ADVANCED) >= {"octree_epsilon", "tolerance", "light_check"}
    panel.octree_epsilon, panel.tolerance, panel.light_check = 0.25, 0.003, 0
    options = addon.job._options(panel)
    assert (options["octree_epsilon"], options["tolerance"], options["light_check"]) == (0.25, 0.003, 0)


def test_without_a_usable_library_the_panel_says_why_and_offers_no_bake(addon, monkeypatch):
    """The settings, their defaults and ranges are the library's alone: without a package
    of this release there are none to show, so the panel says what is wrong instead; the
    artist's settings are still there once the library is."""
    import bpy

    bpy.context.scene.sssbake.resolution = 333
    addon.unregister()
    monkeypatch.setattr(addon.binding, "VERSION", "0.0.0")
    addon.binding.settings.cache_clear()
    addon.register()
    try:
        assert not hasattr(bpy.types.Scene, "sssbake")
        assert not hasattr(bpy.types, "SSSBAKE_OT_bake")
        assert "this add-on is 0.0.0" in addon.panels.MISSING
        assert hasattr(bpy.types, "SSSBAKE_PT_missing_properties")
    finally:
        addon.unregister()
        monkeypatch.undo()
        addon.binding.settings.cache_clear()
        addon.register()
    assert not hasattr(bpy.types, "SSSBAKE_PT_missing_properties")
    assert bpy.context.scene.sssbake.resolution == 333


def test_a_package_of_another_release_is_refused(addon, monkeypatch):
    import sssbake

    binding = addon.binding
    monkeypatch.setattr(binding, "VERSION", "0.0.0")
    with pytest.raises(binding.Error, match=f"is version {sssbake.__version__}, but this add-on is 0.0.0"):
        binding.package()


def xatlas_source():
    """The xatlas.cpp the library is built from: in the xatlas-rs package Cargo resolved."""
    metadata = subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--offline", "--locked"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    )
    package = next(p for p in json.loads(metadata.stdout)["packages"] if p["name"] == "xatlas-rs")
    return pathlib.Path(package["manifest_path"]).parent / "vendor" / "xatlas.cpp"


# Run in a fresh process: the extension as Blender installs it (the wheel it lists unpacked
# into a site folder, the add-on imported as `bl_ext.<repository>.sssbake`) bakes a plane;
# prints where `sssbake` came from and every library of sssbake mapped into the process.
PROBE = """
import json, pathlib, sys
import bpy
sys.path.insert(0, {tests!r})
from conftest import load_extension
addon = load_extension("sssbake", pathlib.Path({extension!r}), repository="user_default")
addon.register()
bpy.ops.mesh.primitive_plane_add(size=1.0)
bpy.ops.object.light_add(type="SUN")
bpy.data.objects["Plane"].select_set(True)
bpy.context.view_layer.objects.active = bpy.data.objects["Plane"]
result = bpy.ops.sssbake.bake(resolution=8, preset="skin1", outputs={{"SUBSURFACE"}})
maps = [line.split()[-1] for line in open("/proc/self/maps") if "sssbake" in line]
print(json.dumps([sorted(result), addon.binding.package().__file__, sorted(set(maps))]))
"""


def test_the_packaged_extension_carries_the_package_as_a_wheel_and_loads_no_shared_library(tmp_path):
    build = subprocess.run(
        [str(ROOT / "scripts" / "build-addon.sh")], capture_output=True, text=True, check=False
    )
    assert build.returncode == 0, build.stderr
    package = next((ROOT / "target").glob("sssbake-*-linux-x64.zip"))
    extension = tmp_path / "extension" / "sssbake"
    with zipfile.ZipFile(package) as archive:
        archive.extractall(extension)
    # The licenses, and xatlas's notice as the source the library is built from states it.
    for notice in ("LICENSE-MIT", "LICENSE-APACHE", "THIRD-PARTY-NOTICES"):
        assert (extension / notice).read_bytes() == (ROOT / notice).read_bytes()
    copyright_line = next(
        line for line in xatlas_source().read_text().splitlines() if line.startswith("Copyright")
    )
    assert copyright_line in (ROOT / "THIRD-PARTY-NOTICES").read_text()
    # One abi3 wheel of the package, listed in the manifest; no library of its own.
    wheels = sorted(p.relative_to(extension).as_posix() for p in extension.glob("wheels/*.whl"))
    assert len(wheels) == 1 and "-abi3-" in wheels[0], wheels
    # Linked for glibc 2.28, as Blender's Linux builds are (maturin audits the symbols).
    assert wheels[0].endswith("-manylinux_2_28_x86_64.whl"), wheels
    import tomllib

    manifest = tomllib.loads((extension / "blender_manifest.toml").read_text())
    assert manifest["wheels"] == [f"./{wheels[0]}"]
    assert not (extension / "lib").exists() and "native.py" not in os.listdir(extension)
    # Blender's own check of an extension (`blender --command extension validate`).
    import bpy

    scripts = pathlib.Path(bpy.utils.system_resource("SCRIPTS"))
    validate = [
        sys.executable,
        str(scripts / "addons_core" / "bl_pkg" / "cli" / "blender_ext.py"),
        "validate",
    ]
    checked = subprocess.run([*validate, str(package)], capture_output=True, text=True, check=False)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    broken = tmp_path / "broken.zip"
    with zipfile.ZipFile(broken, "w") as archive:
        archive.writestr("__init__.py", "")
    assert subprocess.run([*validate, str(broken)], capture_output=True, check=False).returncode != 0
    # Blender installs a wheel by unpacking it into a site folder on its path.
    site = tmp_path / "site"
    with zipfile.ZipFile(extension / wheels[0]) as wheel:
        wheel.extractall(site)
    probe = PROBE.format(tests=str(ROOT / "tests"), extension=str(extension.parent))
    env = {**os.environ, "PYTHONPATH": str(site)}
    loaded = subprocess.run(
        [sys.executable, "-c", probe], cwd=tmp_path, capture_output=True, text=True, check=False, env=env
    )
    assert loaded.returncode == 0, loaded.stderr
    result, origin, libraries = json.loads(loaded.stdout.strip().splitlines()[-1])
    assert result == ["FINISHED"]
    assert pathlib.Path(origin).is_relative_to(site)
    # The package's extension module alone: no libsssbake loaded through ctypes.
    assert libraries and all(pathlib.Path(p).is_relative_to(site / "sssbake") for p in libraries), libraries
    assert not any("libsssbake" in p for p in libraries)


def test_results_saved_to_a_folder_are_openexr_files(addon, tmp_path):
    import bpy

    suzanne_scene()
    folder = tmp_path / "maps"
    result = bpy.ops.sssbake.bake(
        resolution=64,
        method="BRUTE",
        outputs={"SUBSURFACE", "DIFFUSE"},
        destination="FOLDER",
        folder=str(folder),
    )
    assert result == {"FINISHED"}
    assert sorted(p.name for p in folder.iterdir()) == ["Head_diffuse.exr", "Head_subsurface.exr"]
    image = bpy.data.images["Head_subsurface"]
    assert image.packed_file is None and bpy.path.abspath(image.filepath) == str(
        folder / "Head_subsurface.exr"
    )
    saved = exr(folder / "Head_subsurface.exr")[::-1]
    assert np.allclose(saved, pixels("Head_subsurface")[..., :3], rtol=1e-6, atol=1e-7)


def test_unwrapping_bakes_into_a_new_uv_map_the_material_reads(addon):
    import bpy

    head = suzanne_scene()
    result = bpy.ops.sssbake.bake(resolution=64, method="OCTREE", unwrap=True, margin=0, wire_material=True)
    assert result == {"FINISHED"}
    layer = head.data.uv_layers["sssbake"]
    nodes = head.active_material.node_tree.nodes
    assert nodes["sssbake UV"].uv_map == "sssbake"
    assert nodes["sssbake diffuse"].image.name == "Head_diffuse"
    assert nodes["sssbake output"].is_active_output and not nodes["Material Output"].is_active_output
    # The bake follows the new map: faces' UV centroids land on covered texels.
    alpha = pixels("Head_diffuse")[..., 3]
    centroids = np.array(
        [np.mean([layer.data[i].uv for i in polygon.loop_indices], axis=0) for polygon in head.data.polygons]
    )
    rows = np.clip((centroids[:, 1] * 64).astype(int), 0, 63)
    columns = np.clip((centroids[:, 0] * 64).astype(int), 0, 63)
    assert (alpha[rows, columns] > 0).mean() > 0.95


def test_baking_again_updates_the_images_in_place(addon, tmp_path):
    import bpy

    suzanne_scene()
    folder = str(tmp_path / "maps")
    assert bpy.ops.sssbake.bake(
        resolution=64, outputs={"SUBSURFACE"}, destination="FOLDER", folder=folder
    ) == {"FINISHED"}
    first = pixels("Head_subsurface").copy()
    bpy.data.objects["Sun"].data.energy *= 2
    assert bpy.ops.sssbake.bake(resolution=64, outputs={"SUBSURFACE"}) == {"FINISHED"}
    image = bpy.data.images["Head_subsurface"]
    assert len(bpy.data.images) == 1 and image.packed_file is not None
    # Twice the sun, twice the light under the skin, in the same image name.
    covered = first[..., 3] > 0
    assert np.allclose(
        pixels("Head_subsurface")[..., :3][covered], 2 * first[..., :3][covered], rtol=1e-4, atol=1e-6
    )


def test_the_panels_defaults_are_the_librarys(addon):
    import bpy
    import sssbake

    library = sssbake.defaults()
    panel = bpy.context.scene.sssbake
    assert (panel.resolution, panel.margin) == (library["resolution"], library["margin"])
    assert {name.lower() for name in panel.outputs} == set(library["outputs"])
    assert addon.properties.QUALITY_SAMPLES[panel.quality] == library["light_samples"]
    assert panel.max_memory * addon.properties.GIB == library["max_memory_bytes"]
