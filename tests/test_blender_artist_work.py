"""The add-on never loses an artist's work, in a headless bpy: results survive saving and
reopening, images are updated in place through re-bakes, resolution changes and switches
between packed and folder results, a failure at any stage puts the scene back exactly,
Unwrap keeps the artist's UV maps, Show in Material never changes another object, and
folder results never share a file."""

import numpy as np
import pytest
from blender_state import snapshot
from conftest import exr
from test_blender_addon import pixels, suzanne_scene

TINY = {"resolution": 32, "method": "OCTREE", "margin": 0}


def bake(**settings):
    import bpy

    return bpy.ops.sssbake.bake(**{**TINY, **settings})


def test_packed_results_survive_saving_and_reopening(addon, tmp_path):
    import bpy

    suzanne_scene()
    assert bake(outputs={"SUBSURFACE", "AREA"}) == {"FINISHED"}
    before = {name: pixels(name).copy() for name in ("Head_subsurface", "Head_area")}
    path = str(tmp_path / "scene.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    for name, values in before.items():
        assert bpy.data.images[name].use_fake_user
        assert np.array_equal(pixels(name), values), name
    assert bpy.data.images["Head_area"].colorspace_settings.name == "Non-Color"


def test_a_node_keeps_its_image_through_rebakes_resolution_folder_and_reopening(addon, tmp_path):
    import bpy

    head = suzanne_scene()
    sun = bpy.data.objects["Sun"].data
    assert bake(outputs={"DIFFUSE"}, wire_material=True) == {"FINISHED"}
    node = head.active_material.node_tree.nodes["sssbake diffuse"]
    image = node.image
    # The artist's own Image Texture using the result, too.
    own = head.active_material.node_tree.nodes.new("ShaderNodeTexImage")
    own.name = "artist's"
    own.image = image
    first = pixels("Head_diffuse").copy()

    sun.energy *= 2
    assert bake(outputs={"DIFFUSE"}, resolution=48) == {"FINISHED"}
    assert node.image == image and own.image == image and tuple(image.size) == (48, 48)
    assert image.packed_file is not None

    sun.energy *= 2
    folder = tmp_path / "maps"
    assert bake(outputs={"DIFFUSE"}, destination="FOLDER", folder=str(folder)) == {"FINISHED"}
    assert node.image == image and image.packed_file is None and tuple(image.size) == (32, 32)
    on_disk = exr(folder / "Head_diffuse.exr")[::-1]
    covered = first[..., 3] > 0
    # Four times the sun: the image holds the new file's pixels, not the first bake's.
    assert np.allclose(pixels("Head_diffuse")[..., :3], on_disk, rtol=1e-6, atol=1e-7)
    assert np.allclose(on_disk[covered], 4 * first[..., :3][covered], rtol=1e-3, atol=1e-6)

    sun.energy *= 2
    assert bake(outputs={"DIFFUSE"}, destination="FOLDER", folder=str(folder)) == {"FINISHED"}
    path = str(tmp_path / "scene.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    head = bpy.data.objects["Head"]
    nodes = head.active_material.node_tree.nodes
    reopened = nodes["sssbake diffuse"].image
    assert reopened.name == "Head_diffuse" and nodes["artist's"].image == reopened
    assert len(bpy.data.images) == 1
    assert np.allclose(
        pixels("Head_diffuse")[..., :3][covered], 8 * first[..., :3][covered], rtol=1e-3, atol=1e-6
    )


def test_a_rebake_to_a_folder_reads_the_new_file_not_the_packed_pixels(addon, tmp_path):
    import bpy

    suzanne_scene()
    assert bake(outputs={"SUBSURFACE"}) == {"FINISHED"}
    packed = pixels("Head_subsurface").copy()
    bpy.data.objects["Sun"].data.energy *= 3
    folder = tmp_path / "maps"
    assert bake(outputs={"SUBSURFACE"}, destination="FOLDER", folder=str(folder)) == {"FINISHED"}
    covered = packed[..., 3] > 0
    assert np.allclose(
        pixels("Head_subsurface")[..., :3][covered], 3 * packed[..., :3][covered], rtol=1e-3, atol=1e-6
    )


STAGES = {
    # Before the bake: the scene could not be sent to the library (after Unwrap ran).
    "before": ("scene_export", "build_scene"),
    # During: the library failed.
    "during": ("binding", "bake"),
    # While making the images: the second image fails, after the first was updated.
    "images": ("images", "store_packed"),
    # While wiring Show in Material.
    "wiring": ("wiring", "_wire"),
}


def _fail_at(addon, monkeypatch, stage, after=0):
    module_name, function_name = STAGES[stage]
    module = getattr(addon, module_name)
    original = getattr(module, function_name)
    calls = []

    def failing(*args, **kwargs):
        calls.append(1)
        if len(calls) > after:
            raise RuntimeError(f"injected failure {stage}")
        return original(*args, **kwargs)

    monkeypatch.setattr(module, function_name, failing)


@pytest.mark.parametrize("stage", list(STAGES))
def test_a_failure_at_any_stage_leaves_the_scene_as_it_was(addon, monkeypatch, capfd, stage):
    import bpy

    head = suzanne_scene()
    # An earlier bake the failure must not touch, and the artist in Edit Mode.
    assert bake(outputs={"DIFFUSE", "SUBSURFACE"}) == {"FINISHED"}
    bpy.data.objects["Sun"].data.energy *= 2
    bpy.ops.object.mode_set(mode="EDIT")
    before = snapshot()
    assert before["images"] and before["objects"]["Head"]["mode"] == "EDIT"
    _fail_at(addon, monkeypatch, stage, after=1 if stage == "images" else 0)
    result = bake(outputs={"DIFFUSE", "SUBSURFACE"}, unwrap=True, wire_material=True)
    assert result == {"CANCELLED"}
    assert f"injected failure {stage}" in capfd.readouterr().out
    assert snapshot() == before
    assert head.mode == "EDIT"


def test_a_failed_bake_keeps_unsaved_painting_on_a_result(addon, monkeypatch):
    import bpy

    suzanne_scene()
    assert bake(outputs={"DIFFUSE"}) == {"FINISHED"}
    image = bpy.data.images["Head_diffuse"]
    painted = np.linspace(0.0, 1.0, len(image.pixels), dtype=np.float32)
    image.pixels.foreach_set(painted)  # as Texture Paint would: in memory, unsaved
    assert image.is_dirty
    _fail_at(addon, monkeypatch, "wiring")
    assert bake(outputs={"DIFFUSE"}, resolution=48, wire_material=True) == {"CANCELLED"}
    assert tuple(image.size) == (32, 32)
    assert np.array_equal(pixels("Head_diffuse").reshape(-1), painted)


def test_a_folder_that_cannot_be_made_leaves_the_scene_as_it_was(addon, tmp_path, capfd):
    head = suzanne_scene()
    blocker = tmp_path / "file"
    blocker.write_text("in the way")
    before = snapshot()
    result = bake(unwrap=True, destination="FOLDER", folder=str(blocker / "maps"))
    assert result == {"CANCELLED"}
    assert "cannot make the folder" in capfd.readouterr().out
    assert snapshot() == before
    assert "sssbake" not in head.data.uv_layers


def test_a_failure_after_the_files_leaves_the_folder_as_it_was(addon, monkeypatch, tmp_path):
    suzanne_scene()
    folder = tmp_path / "maps"
    assert bake(outputs={"DIFFUSE", "SUBSURFACE"}, destination="FOLDER", folder=str(folder)) == {"FINISHED"}
    import bpy

    bpy.data.objects["Sun"].data.energy *= 2
    before = snapshot(folder)
    _fail_at(addon, monkeypatch, "wiring")
    result = bake(
        outputs={"DIFFUSE", "SUBSURFACE"}, destination="FOLDER", folder=str(folder), wire_material=True
    )
    assert result == {"CANCELLED"}
    assert snapshot(folder) == before


def test_unwrap_keeps_the_artists_fixes_and_active_map(addon, capfd):
    import bpy

    head = suzanne_scene()
    layers = head.data.uv_layers
    assert layers.active.name == "UVMap"
    assert bake(unwrap=True) == {"FINISHED"}
    assert layers.active.name == "UVMap" and layers["UVMap"].active_render
    # The artist fixes a corner of the map; a second bake keeps it.
    layers["sssbake"].data[0].uv = (0.123, 0.456)
    assert bake(unwrap=True) == {"FINISHED"}
    assert tuple(layers["sssbake"].data[0].uv) == pytest.approx((0.123, 0.456))
    output = capfd.readouterr().out
    assert "as they are" not in output and "tick Unwrap" not in output.replace("Unwrap Again", "")
    assert bake(unwrap=True, redo_unwrap=True) == {"FINISHED"}
    assert tuple(layers["sssbake"].data[0].uv) != pytest.approx((0.123, 0.456))
    assert layers.active.name == "UVMap" and len(bpy.data.images) == 3


def test_unwrap_uses_the_librarys_xatlas_and_keeps_smart_uv_project_as_a_choice(addon, capfd):
    import bpy

    head = suzanne_scene()
    assert bpy.context.scene.sssbake.unwrap_method == "XATLAS"
    assert bake(unwrap=True, resolution=64, margin=2, outputs={"AREA"}) == {"FINISHED"}
    # The library finds the map usable at this resolution: no overlap, mirror or stretch.
    assert "UV map `sssbake` has" not in capfd.readouterr().out
    mesh = head.data
    layer = mesh.uv_layers["sssbake"]
    uv = np.array([loop.uv[:] for loop in layer.data])
    assert ((uv >= 0) & (uv <= 1)).all()
    # Faces counter-clockwise (xatlas may hand charts back mirrored), each face's corners
    # one UV each; a face xatlas cut in two is placed by its larger triangle's mapping,
    # which may fold a sliver of the other: at most 1% of the triangles.
    mesh.calc_loop_triangles()
    signed = np.array(
        [
            np.cross(uv[t.loops[1]] - uv[t.loops[0]], uv[t.loops[2]] - uv[t.loops[0]])
            for t in mesh.loop_triangles
        ]
    )
    assert (signed < 0).mean() <= 0.01 and np.abs(signed[signed < 0]).max(initial=0) < np.median(
        np.abs(signed)
    )
    xatlas = uv.copy()
    assert bake(unwrap=True, unwrap_method="SMART", redo_unwrap=True, outputs={"AREA"}) == {"FINISHED"}
    # Smart UV Project goes through Edit Mode, which rebuilds the mesh's layers: a Python
    # reference taken before it points at freed memory, so look the layer up again.
    smart = np.array([loop.uv[:] for loop in mesh.uv_layers["sssbake"].data])
    assert not np.allclose(smart, xatlas)


def test_a_bake_from_edit_mode_returns_to_edit_mode_with_the_edits(addon):
    import bpy

    head = suzanne_scene()
    bpy.ops.object.mode_set(mode="EDIT")
    assert bake(outputs={"AREA"}, unwrap=True) == {"FINISHED"}
    assert head.mode == "EDIT"
    area = pixels("Head_area")
    # An edit made in Edit Mode is baked: scaling the mesh scales its area per texel.
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.transform.resize(value=(2.0, 2.0, 2.0))
    assert bake(outputs={"AREA"}, unwrap=True) == {"FINISHED"}
    assert head.mode == "EDIT"
    covered = area[..., 3] > 0
    assert np.allclose(pixels("Head_area")[..., 0][covered], 4 * area[..., 0][covered], rtol=1e-3)


def _twins():
    """Suzanne and a copy of her sharing her material, both selected."""
    import bpy

    head = suzanne_scene()
    twin = head.copy()
    twin.data = head.data.copy()
    twin.name = "Twin"
    twin.location.x += 0.5
    bpy.context.collection.objects.link(twin)
    twin.select_set(True)
    return head, twin


def test_show_in_material_leaves_a_shared_material_alone_and_says_so(addon, capfd):
    _twins()
    before = snapshot()["materials"]
    assert bake(outputs={"DIFFUSE"}, wire_material=True) == {"FINISHED"}
    assert snapshot()["materials"] == before
    output = capfd.readouterr().out
    assert "material `Skin` is shared with `Twin`, so it was left as it is" in output
    assert "material `Skin` is shared with `Head`, so it was left as it is" in output


def test_show_in_material_gives_each_object_its_own_copy_on_request(addon):
    import bpy

    head, twin = _twins()
    other = bpy.data.objects.new("Bystander", head.data)  # not baked, shares the mesh too
    bpy.context.collection.objects.link(other)
    assert bake(outputs={"DIFFUSE"}, wire_material=True, copy_shared_materials=True) == {"FINISHED"}
    for obj in (head, twin):
        material = obj.active_material
        assert material.name == f"Skin ({obj.name})"
        assert material.node_tree.nodes["sssbake diffuse"].image.name == f"{obj.name}_diffuse"
        assert material.node_tree.nodes["sssbake output"].is_active_output
    original = bpy.data.materials["Skin"]
    assert other.active_material == original and "sssbake output" not in original.node_tree.nodes


def test_folder_results_of_similar_names_never_share_a_file(addon, tmp_path):
    import bpy

    head = suzanne_scene()
    names = ["Arm.L", "Arm_L", "arm_l"]
    for i, name in enumerate(names):
        copy = head.copy()
        copy.data = head.data.copy()
        copy.name = name
        copy.location.x += 0.4 * (i + 1)
        bpy.context.collection.objects.link(copy)
        copy.select_set(True)
    head.select_set(False)
    bpy.data.objects["Sun"].data.energy = 1.0
    folder = tmp_path / "maps"
    assert bake(outputs={"AREA"}, destination="FOLDER", folder=str(folder)) == {"FINISHED"}
    paths = {bpy.path.abspath(bpy.data.images[f"{n}_area"].filepath) for n in names}
    assert len(paths) == 3
    # The library's rule, as the CLI names files: `.` is kept, and names equal but for
    # case (as some file systems see them) get `-2` in the scene's order.
    files = sorted(p.name for p in folder.iterdir())
    assert len(files) == 3 and "Arm.L_area.exr" in files
    assert {"Arm_L_area.exr", "arm_l-2_area.exr"} <= set(files) or {
        "arm_l_area.exr",
        "Arm_L-2_area.exr",
    } <= set(files)
    for name in names:
        image = bpy.data.images[f"{name}_area"]
        assert np.allclose(pixels(image.name)[..., :3], exr(bpy.path.abspath(image.filepath))[::-1])
