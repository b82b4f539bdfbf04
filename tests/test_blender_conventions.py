"""The add-on follows Blender's conventions, in a headless bpy: a tooltip on every setting
with its unit, blend-relative folders (refused while the .blend is unsaved), poll(), a menu
entry, one undo step and no redo panel, reports that say how each object was baked, and
progress lines in background mode."""

import re

from conftest import ROOT
from test_blender_addon import suzanne_scene

TINY = {"resolution": 32, "method": "OCTREE", "margin": 2}


def test_every_setting_has_a_description_and_units_where_it_has_them(addon):
    import bpy

    operator = bpy.ops.sssbake.bake.get_rna_type().properties
    panel = bpy.context.scene.sssbake.bl_rna.properties
    for properties in (operator, panel):
        for name in addon.properties.SETTING_NAMES:
            assert properties[name].description.strip(), name
    properties = panel
    assert "texels per side" in properties["resolution"].description
    assert "pixels" in properties["margin"].description
    assert "light samples" in properties["quality"].description.lower()
    assert properties["folder"].subtype == "DIR_PATH"


def test_the_operator_is_in_the_object_menu_with_one_undo_step_and_no_redo_panel(addon):
    import bpy

    assert addon.operators.menu_entry in bpy.types.VIEW3D_MT_object._dyn_ui_initialize()
    options = bpy.types.SSSBAKE_OT_bake.bl_options
    assert "UNDO" in options and "REGISTER" not in options
    # Never remembered between calls: a bake from the interface takes the panel's settings.
    operator = bpy.ops.sssbake.bake.get_rna_type().properties
    assert all(operator[name].is_skip_save for name in addon.properties.SETTING_NAMES)


def test_a_blend_relative_folder_is_refused_until_the_file_is_saved(addon, tmp_path, capfd):
    import bpy

    suzanne_scene()
    settings = {**TINY, "outputs": {"AREA"}, "destination": "FOLDER", "folder": "//maps"}
    assert bpy.ops.sssbake.bake(**settings) == {"CANCELLED"}
    assert "relative to the .blend file (`//`), which is not saved yet" in capfd.readouterr().out
    assert len(bpy.data.images) == 0
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "scene.blend"))
    assert bpy.ops.sssbake.bake(**settings) == {"FINISHED"}
    image = bpy.data.images["Head_area"]
    # The image keeps the path relative, so the .blend and its folder move together.
    assert image.filepath == "//maps/Head_area.exr"
    assert (tmp_path / "maps" / "Head_area.exr").is_file()


def test_the_report_says_how_each_object_was_baked_and_background_bakes_print_progress(addon, capfd):
    import bpy

    suzanne_scene()
    assert bpy.app.background
    assert bpy.ops.sssbake.bake(**{**TINY, "method": "AUTO"}, outputs={"SUBSURFACE"}) == {"FINISHED"}
    out = capfd.readouterr().out
    line = next(line for line in out.splitlines() if line.startswith("Info: sssbake: Head;"))
    # The method, why auto chose it, its estimated error and each stage's seconds.
    assert re.search(r"Head; (octree|texture|importance|brute) \([^)]+\)", line), line
    assert re.search(r"estimated error [0-9.e+-]+%", line), line
    # And its distance from light: a random walk through the mesh, its noise stated.
    assert re.search(
        r"against light [0-9.e+-]+% \(a random walk at \d+ texels, its noise [0-9.e+-]+%\)", line
    ), line
    for stage in ("layout", "lighting", "scattering"):
        assert re.search(rf"{stage} [0-9.]+ s", line), line
    progress = re.findall(r"^sssbake: Head (\d+)%$", out, flags=re.MULTILINE)
    assert progress and progress[0] == "0" and progress[-1] == "100", out


def test_the_guide_lists_every_setting(addon):
    import bpy

    guide = (ROOT / "docs" / "blender.md").read_text()
    panel = bpy.context.scene.sssbake.bl_rna.properties
    for name in addon.properties.SETTING_NAMES:
        assert f"| {panel[name].name} |" in guide, panel[name].name
