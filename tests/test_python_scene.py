"""`sssbake.Scene`: a scene built from a host's own arrays and baked from Python. A texel's
area is the square's in millimetres whatever the scene's unit; the subsurface light is
linear in the lights (a sun twice as strong, a sun and a world together); a face slot
without subsurface stays empty while the summary counts each slot's texels; progress rises
to 1 across the slots' bakes; a cancel stops it with nothing changed; a folder bake writes
the maps alone, whole; unwrapped charts run counter-clockwise; bad arrays, lights,
materials and options are the package's exceptions naming the object and the field."""

import threading

import numpy as np
import pytest
import sssbake

# A square of side 0.1 units in the z = 0 plane facing +z, its UVs covering the map; its
# first triangle (v < u) and its second (v > u) split the map along the diagonal.
CORNERS = np.array([[-0.05, -0.05, 0.0], [0.05, -0.05, 0.0], [0.05, 0.05, 0.0], [-0.05, 0.05, 0.0]])
TRIANGLES = [0, 1, 2, 0, 2, 3]
UVS = [[0, 0], [1, 0], [1, 1], [0, 1]]
SKIN = {"kind": "preset", "name": "skin1"}


def square(millimetres_per_unit=1000.0, scale=1.0, **mesh):
    scene = sssbake.Scene(millimetres_per_unit)
    scene.add_mesh("Card", CORNERS * scale, TRIANGLES, uvs=UVS, **mesh)
    return scene


def test_a_texels_area_is_the_squares_in_millimetres_whatever_the_unit():
    # 0.1 m, and 10 cm given in centimetres: both a 100 mm square, 10^4 mm² in 32² texels.
    for scene in (square(1000.0), square(10.0, scale=100.0)):
        area = scene.bake_object("Card", [SKIN], resolution=32, margin=0, outputs=["area"]).image("area")
        covered = area[..., 3] > 0
        assert covered.all()
        assert area[..., 0][covered].sum() == pytest.approx(1e4, rel=1e-3)


def subsurface(scene, **options):
    result = scene.bake_object(
        "Card", [SKIN], resolution=16, method="brute", outputs=["subsurface"], **options
    )
    return result.image("subsurface")


def test_the_subsurface_light_is_linear_in_the_lights():
    one, two, world, both = (square() for _ in range(4))
    one.add_light("sun", power=1.0)
    two.add_light("sun", power=2.0)
    world.set_world((0.5, 0.4, 0.3), 2.0)
    both.add_light("sun", power=1.0)
    both.set_world((0.5, 0.4, 0.3), 2.0)
    a, b, w, ab = (subsurface(s)[..., :3] for s in (one, two, world, both))
    assert a.min() > 0 and w.min() > 0
    np.testing.assert_allclose(b, 2 * a, rtol=1e-5)
    # The world is sampled (Monte Carlo over the sky, a few per cent per texel, drawn
    # differently beside a sun), so the sum holds on average over the card.
    np.testing.assert_allclose(ab.mean(axis=(0, 1)), (a + w).mean(axis=(0, 1)), rtol=5e-3)
    # A light facing away lights nothing; a misspelt field is refused by name.
    away = square()
    away.add_light("sun", power=1.0, direction=(0, 0, 1))
    assert subsurface(away)[..., :3].max() == 0
    with pytest.raises(sssbake.SettingError, match="unknown field `powr`") as error:
        away.add_light("sun", powr=1.0)
    assert error.value.field == "light"


def test_a_slot_without_subsurface_stays_empty_and_the_summary_counts_each_slots_texels():
    scene = square(material_indices=[0, 1])
    scene.add_light("sun", power=1.0)
    wax = {"kind": "principled", "name": "Wax", "base_colour": (0.9, 0.8, 0.6), "subsurface_weight": 1.0}
    cloth = {"kind": "none", "name": "Cloth"}
    seen = []
    result = scene.bake_object(
        "Card", [wax, cloth], resolution=32, margin=0, progress=lambda f, s: seen.append(f)
    )
    image = result.image("subsurface")
    v, u = np.mgrid[0:32, 0:32] + 0.5
    lower, upper = v < u - 1, v > u + 1  # texel centres clear of the diagonal
    assert (image[..., 3][lower] == 1).all() and (image[..., :3][lower] > 0).all()
    assert (image[..., 3][upper] == 0).all() and (image[..., :3][upper] == 0).all()
    rows = result.summary["objects"][0]["materials"]
    assert [(r["name"], r["index"]) for r in rows] == [("Wax", 0), ("Cloth", 1)]
    assert rows[0]["texels"] == int((image[..., 3] > 0).sum()) and rows[1]["texels"] == 0
    assert seen and seen[-1] == 1.0 and seen == sorted(seen)
    # With both slots of wax the whole square is covered.
    whole = scene.bake_object("Card", [wax, wax], resolution=32, margin=0).image("subsurface")
    assert (whole[..., 3] == 1).all()


def test_an_image_colours_its_slot_through_the_uvs():
    scene = square()
    scene.add_light("sun", power=1.0)
    # A 2 × 1 image: black left half, white right half (linear RGB, rows from v = 0 up).
    pixels = np.array([[[0.05, 0.05, 0.05], [0.9, 0.9, 0.9]]], dtype=np.float32)
    image = {"pixels": pixels, "width": 2, "height": 1, "channels": 3, "extension": "EXTEND", "nearest": True}
    wax = {"kind": "principled", "base_colour": (0.5, 0.5, 0.5), "subsurface_weight": 1.0, "image": image}
    maps = scene.bake_object("Card", [wax], resolution=16, outputs=["diffuse"]).image("diffuse")
    assert maps[:, 12:, :3].mean() > 3 * maps[:, :4, :3].mean()
    with pytest.raises(sssbake.SettingError, match="holds 5 floats") as error:
        scene.bake_object("Card", [{**wax, "image": {**image, "pixels": np.zeros(5)}}], resolution=16)
    assert error.value.field == "image"


def test_a_cancel_stops_the_bake_and_the_scene_bakes_again():
    scene = square()
    scene.add_light("sun", power=1.0)
    stop = threading.Event()
    stop.set()
    with pytest.raises(sssbake.Cancelled):
        scene.bake_object("Card", [SKIN], resolution=16, cancel=stop)
    assert scene.objects == ["Card"]
    assert scene.bake_object("Card", [SKIN], resolution=16).resolution == 16


def test_a_folder_bake_writes_the_maps_alone_and_keeps_what_is_there(tmp_path):
    scene = square()
    scene.add_light("point", power=100.0, position=(0, 0, 0.2))
    summary = scene.bake(tmp_path / "maps", resolution=16, outputs=["subsurface", "area"], preset="marble")
    assert sorted(p.name for p in (tmp_path / "maps").iterdir()) == [
        "Card_area.exr",
        "Card_subsurface.exr",
        "Card_subsurface.png",
    ]
    assert summary["objects"][0]["material"]["name"] == "marble"
    before = (tmp_path / "maps" / "Card_subsurface.exr").read_bytes()
    with pytest.raises(sssbake.OutputError, match="exists"):
        scene.bake(tmp_path / "maps", resolution=8, outputs=["subsurface"])
    assert (tmp_path / "maps" / "Card_subsurface.exr").read_bytes() == before


def test_unwrapped_charts_lie_in_the_map_and_run_counter_clockwise():
    # A cube, one vertex per corner of each triangle, as a host with split normals has it.
    corners = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=np.float32)
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    triangles = np.array([[f[0], f[1], f[2], f[0], f[2], f[3]] for f in faces]).reshape(-1)
    positions = corners[triangles]
    indices = np.arange(len(triangles))
    uvs, charts = sssbake.unwrap("Cube", positions, indices, 64, 2)
    assert uvs.shape == (2 * len(indices),) and charts.shape == (len(indices) // 3,)
    assert uvs.min() >= 0 and uvs.max() <= 1
    corner = uvs.reshape(-1, 3, 2)
    signed = np.cross(corner[:, 1] - corner[:, 0], corner[:, 2] - corner[:, 0])
    assert (signed > 0).all()


def test_bad_arrays_materials_and_options_name_the_object_and_the_field():
    scene = square()
    with pytest.raises(sssbake.SettingError, match="object `Bad`: 5 position floats") as error:
        scene.add_mesh("Bad", np.zeros(5), [0, 1, 2])
    assert error.value.field == "mesh"
    with pytest.raises(sssbake.InputError, match="index 7 but 4 vertices") as error:
        scene.add_mesh("Broken", CORNERS, [0, 1, 7])
    assert error.value.object == "Broken"
    with pytest.raises(sssbake.SettingError, match="one of that name already"):
        scene.add_mesh("Card", CORNERS, TRIANGLES)
    with pytest.raises(sssbake.SettingError, match="millimetres per unit is 0"):
        sssbake.Scene(0.0)
    with pytest.raises(sssbake.InputError, match="no object named `Nobody`"):
        scene.bake_object("Nobody", [SKIN], resolution=8)
    with pytest.raises(sssbake.SettingError, match="`glass` is not") as error:
        scene.bake_object("Card", [{"kind": "glass"}], resolution=8)
    assert error.value.field == "materials[0].kind"
    with pytest.raises(sssbake.SettingError, match="needs its kind") as error:
        scene.bake_object("Card", [{"name": "Skin"}], resolution=8)
    assert error.value.field == "materials[0].kind"
    with pytest.raises(sssbake.SettingError, match="unknown field `colour`") as error:
        scene.bake_object("Card", [{"kind": "principled", "colour": (1, 1, 1)}], resolution=8)
    with pytest.raises(sssbake.SettingError) as error:
        scene.bake_object("Card", [SKIN], preset="marble")
    assert error.value.field == "preset"
    with pytest.raises(sssbake.SettingError) as error:
        scene.bake_object("Card", [SKIN], unit_scale=10.0)
    assert error.value.field == "unit_scale"
    with pytest.raises(sssbake.InputError, match="unknown preset `jelly`"):
        scene.bake_object("Card", [{"kind": "preset", "name": "jelly"}], resolution=8)
    assert scene.objects == ["Card"]
