"""The `sssbake` Python package (pyproject.toml, rust/python, python/sssbake), installed
into the test venv by scripts/test.sh: the examples of the README and docs/python.md run
as written; a bake from Python equals the binary's bit for bit, from a file and from a USD
stage in memory; progress rises to 1; cancellation, Ctrl-C-like callback errors and the library's errors
arrive as the package's exceptions; the GIL is free while the library works; profiles are
numpy arrays whose integral is the profile's total reflectance."""

import json
import os
import pathlib
import re
import shutil
import threading
import time

import numpy as np
import pytest
import sssbake
from conftest import ROOT, exr, run

HEAD = ROOT / "examples" / "head" / "head.gltf"
HEAD_USD = ROOT / "examples" / "head" / "head.usda"
MARBLE = ROOT / "examples" / "marble" / "marble.gltf"


def test_the_package_is_the_built_library_and_typed():
    assert (
        sssbake.__version__
        == re.search(r'^version = "(.+)"', (ROOT / "Cargo.toml").read_text(), re.MULTILINE)[1]
    )
    package = pathlib.Path(sssbake.__file__).parent
    assert (package / "py.typed").exists()
    assert (package / "_native.pyi").exists()
    assert "skin1" in sssbake.presets()


def python_blocks(page: pathlib.Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", page.read_text(), re.DOTALL)


def test_the_readmes_python_example_runs(tmp_path, monkeypatch):
    blocks = python_blocks(ROOT / "README.md")
    assert len(blocks) >= 1
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, "README.md", "exec"), namespace)  # noqa: S102 - the README under test
    assert namespace["head"]["accuracy"]["method"]
    # The Python result states the error against light, with the walk's noise.
    light = namespace["head"]["accuracy"]["light"]
    assert light["texels"] > 0 and 0 < light["walk_noise"] < 1 and light["estimated_error"] >= 0
    assert all(pathlib.Path(f).exists() for f in namespace["summary"]["files"])


def test_the_python_pages_examples_run(tmp_path, monkeypatch):
    blocks = python_blocks(ROOT / "docs" / "python.md")
    assert len(blocks) >= 3
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, "docs/python.md", "exec"), namespace)  # noqa: S102 - the page under test
    # What the examples claim they did.
    assert namespace["head"]["accuracy"]["method"]
    assert all(pathlib.Path(f).exists() for f in namespace["summary"]["files"])
    assert namespace["stage"].GetRootLayer().subLayerPaths[0].endswith("baked/head_usd/head_sssbake.usda")
    assert namespace["two_layer"]["reflectance"].shape == (3, 3)
    card = namespace["card"].summary["objects"][0]["materials"]
    assert [m["name"] for m in card] == ["skin1", "Wax"] and all(m["texels"] > 0 for m in card)
    assert (tmp_path / "baked" / "card_diffuse.exr").exists()
    assert sorted(p.name for p in (tmp_path / "baked" / "card").iterdir()) == [
        "Card_subsurface.exr",
        "Card_subsurface.png",
    ]


def maps(folder: pathlib.Path) -> dict:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.suffix in (".exr", ".png")}


def test_a_bake_from_python_equals_the_binarys_bit_for_bit(sssbake, tmp_path):
    import sssbake as package  # the fixture's name shadows the module

    options = ["--resolution", "64", "--outputs", "subsurface,irradiance,diffuse"]
    done = run(sssbake, "bake", str(HEAD), "--out", str(tmp_path / "cli"), *options)
    assert done.returncode == 0, done.stderr
    summary = package.bake(
        HEAD, tmp_path / "py", resolution=64, outputs=("subsurface", "irradiance", "diffuse")
    )
    assert maps(tmp_path / "cli") == maps(tmp_path / "py")
    assert len(maps(tmp_path / "py")) >= 6
    assert {pathlib.Path(f).name for f in summary["files"]} >= set(maps(tmp_path / "py"))
    assert summary["objects"][0]["name"] == "Head"


def test_a_stage_in_memory_bakes_as_its_file_and_gets_the_look(tmp_path):
    from pxr import Usd, UsdShade

    from_file = sssbake.bake(HEAD_USD, tmp_path / "file", resolution=64)
    stage = Usd.Stage.Open(str(HEAD_USD))
    sssbake.bake(stage, tmp_path / "stage", resolution=64)
    assert maps(tmp_path / "file") == maps(tmp_path / "stage")
    assert (tmp_path / "file" / "head_sssbake.usda").read_text() == (
        tmp_path / "stage" / "head_sssbake.usda"
    ).read_text()

    # Only in memory, and edited there: the edit is baked (every light at half its
    # intensity gives half the irradiance) and the look is composed onto that stage.
    memory = Usd.Stage.CreateInMemory("shot.usda")
    memory.GetRootLayer().TransferContent(stage.GetRootLayer())
    for light in (p for p in memory.Traverse() if p.HasAttribute("inputs:intensity")):
        intensity = light.GetAttribute("inputs:intensity")
        intensity.Set(intensity.Get() / 2)
    before = memory.GetRootLayer().ExportToString()
    summary = sssbake.bake(memory, tmp_path / "memory", resolution=64, look_on=memory)
    halved = exr(tmp_path / "memory" / "Head_irradiance.exr")
    full = exr(tmp_path / "file" / "Head_irradiance.exr")
    assert full.max() > 0
    np.testing.assert_allclose(halved, full / 2, rtol=1e-5, atol=1e-7)
    layer = tmp_path / "memory" / "shot_sssbake.usda"
    assert memory.GetRootLayer().subLayerPaths[0] == str(layer)
    mesh = next(p for p in memory.Traverse() if p.GetTypeName() == "Mesh")
    bound = UsdShade.MaterialBindingAPI(mesh).ComputeBoundMaterial()[0]
    assert bound.GetPath().name == summary["objects"][0]["file_stem"]
    assert bound.GetPrim().GetAttribute("sssbake:resolution").Get() == "64"
    # Nothing else of the stage changed: only the sublayer was added.
    memory.GetRootLayer().subLayerPaths.clear()
    assert memory.GetRootLayer().ExportToString() == before
    assert from_file["objects"][0]["name"] == summary["objects"][0]["name"]


def test_progress_rises_to_one_and_the_gil_is_free_meanwhile(tmp_path):
    seen = []
    ticks = 0
    running = True

    def count():
        nonlocal ticks
        while running:
            ticks += 1
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    try:
        start = time.monotonic()
        sssbake.bake(MARBLE, tmp_path, resolution=512, progress=lambda f, s: seen.append((f, s)))
        seconds = time.monotonic() - start
    finally:
        running = False
        counter.join()
    fractions = [f for f, _ in seen]
    assert len(fractions) >= 3
    assert fractions == sorted(fractions)
    assert fractions[-1] == 1.0
    assert all(0.0 <= f <= 1.0 for f in fractions)
    # A thread that needs the GIL ran throughout (with the GIL held it could not tick):
    # about one tick a millisecond, here asked for one in every ten.
    assert ticks > 100 * seconds


def test_a_cancel_event_or_a_failing_callback_stops_the_bake_and_leaves_nothing(tmp_path):
    stop = threading.Event()

    def cancel_soon(fraction, stage):
        stop.set()

    with pytest.raises(sssbake.Cancelled) as cancelled:
        sssbake.bake(MARBLE, tmp_path / "a", resolution=256, progress=cancel_soon, cancel=stop)
    assert cancelled.value.kind == "cancelled"
    assert not (tmp_path / "a").exists() or not any((tmp_path / "a").iterdir())

    class Stop(Exception):
        pass

    def fail(fraction, stage):
        raise Stop("the artist pressed Esc")

    with pytest.raises(Stop, match="pressed Esc"):
        sssbake.bake(MARBLE, tmp_path / "b", resolution=256, progress=fail)
    assert not (tmp_path / "b").exists() or not any((tmp_path / "b").iterdir())


def test_the_librarys_errors_are_exceptions_naming_kind_file_and_field(tmp_path):
    with pytest.raises(sssbake.SettingError) as setting:
        sssbake.bake(HEAD, tmp_path, resolution=0)
    assert setting.value.field == "resolution" and "between 1" in setting.value.message

    with pytest.raises(sssbake.SettingError) as unknown:
        sssbake.plan(HEAD, resolutoin=64)
    assert unknown.value.field == "options" and "resolutoin" in unknown.value.message

    broken = tmp_path / "broken.gltf"
    broken.write_text(
        '{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 99}}]}]}'
    )
    with pytest.raises(sssbake.InputError) as bad:
        sssbake.bake(broken, tmp_path / "out", resolution=8)
    assert bad.value.kind == "input" and bad.value.file == str(broken)
    assert not (tmp_path / "out").exists()

    (tmp_path / "taken").mkdir()
    sssbake.bake(MARBLE, tmp_path / "taken", resolution=16)
    with pytest.raises(sssbake.OutputError) as exists:
        sssbake.bake(MARBLE, tmp_path / "taken", resolution=16)
    assert "exists" in exists.value.message
    sssbake.bake(MARBLE, tmp_path / "taken", resolution=16, force=True)

    with pytest.raises(sssbake.SettingError, match="only a USD scene") as no_layer:
        sssbake.bake(MARBLE, tmp_path / "gltf", resolution=16, look_on=object())
    assert no_layer.value.field == "look_on" and not (tmp_path / "gltf").exists()

    # A work limit is named as this package's argument, not the command line's option.
    with pytest.raises(sssbake.SettingError) as limit:
        sssbake.plan(MARBLE, resolution=64, max_memory="1M")
    assert limit.value.field == "max_memory"
    assert limit.value.message.endswith("raise the limit (the max_memory argument)")
    assert "--max-memory" not in limit.value.message

    with pytest.raises(sssbake.InputError, match="unknown preset"):
        sssbake.profile("no-such-preset")
    with pytest.raises(sssbake.SettingError):
        sssbake.profile("skin1", epsilon=2.0)


def test_a_profiles_arrays_integrate_to_its_total_reflectance():
    skin = sssbake.profile("skin1", radii=np.geomspace(1e-5, 40.0, 20000))
    r, R = skin["radii_mm"], skin["reflectance"]
    assert r.shape == (20000,) and R.shape == (20000, 3) and R.dtype == np.float64
    assert np.all(np.isfinite(R)) and np.all(R >= 0)
    # 2πr R(r) by the trapezoid rule, an integral independent of the library's own totals.
    integrand = 2 * np.pi * r[:, None] * R
    integral = ((integrand[1:] + integrand[:-1]) / 2 * np.diff(r)[:, None]).sum(axis=0)
    np.testing.assert_allclose(integral, skin["total_reflectance"], rtol=5e-3)
    assert np.all(skin["d_max_mm"] > 0)
    default = sssbake.profile("skin1")
    assert default["radii_mm"].shape == (60,)
    assert default["radii_mm"][-1] == pytest.approx(default["d_max_mm"].max())


def test_a_profile_plot_and_a_report_come_to_python_as_to_the_command_line(sssbake, tmp_path):
    """The analysis is the library's: Python gets the plot `sssbake profile --plot` draws,
    and the error-against-time report `sssbake report` writes, run for run."""
    import sssbake as package  # the fixture's name shadows the module

    binary = sssbake
    svg = package.profile_plot("skin1", radii=[0.1, 1.0, 3.0])
    drawn = tmp_path / "skin1.svg"
    result = run(binary, "profile", "--preset", "skin1", "--radii", "0.1,1,3", "--plot", str(drawn))
    assert result.returncode == 0, result.stderr
    assert svg.startswith("<svg") and svg == drawn.read_text()

    # The arrays are the profile `sssbake profile` prints, model for model.
    for model in ("dipole", "multipole", "burley"):
        table = package.profile("skin1", model=model, radii=[0.1, 1.0, 3.0])
        result = run(binary, "profile", "--preset", "skin1", "--model", model, "--radii", "0.1,1,3", "--json")
        assert result.returncode == 0, result.stderr
        printed = json.loads(result.stdout)
        assert table["model"] == printed["model"] == model
        for key in ("radii_mm", "reflectance", "transmittance", "total_reflectance", "d_max_mm"):
            np.testing.assert_allclose(table[key], printed[key], rtol=1e-12, err_msg=f"{model} {key}")
    with pytest.raises(package.SettingError, match="increase"):
        package.profile("skin1", radii=[1.0, 0.5])

    report = package.report(MARBLE, tmp_path / "python", resolution=12, light_samples=2)
    cli = tmp_path / "cli"
    result = run(
        binary, "report", str(MARBLE), "--out", str(cli), "--resolution", "12", "--light-samples", "2"
    )
    assert result.returncode == 0, result.stderr
    written = json.loads((cli / "report.json").read_text())
    same = lambda runs: [(r["method"], r["setting"], round(r["relative_rmse"], 9)) for r in runs]
    assert same(report["runs"]) == same(written["runs"])
    assert report["runs"][0]["method"] == "brute" and any(r["pareto"] for r in report["runs"])
    assert {p.name for p in (tmp_path / "python").iterdir()} >= {"report.json", "report.png", "report.csv"}
    with pytest.raises(package.OutputError, match="exists"):
        package.report(MARBLE, tmp_path / "python", resolution=12)


def test_a_batch_from_python_reports_each_asset_and_skips_on_a_rerun(tmp_path):
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    manifest = tmp_path / "examples" / "batch.toml"
    manifest.write_text(
        '[defaults]\nresolution = 32\n\n[assets.marble]\nscene = "marble/marble.gltf"\n\n'
        '[assets.broken]\nscene = "marble/missing.gltf"\n'
    )
    ended = []
    report = sssbake.batch(manifest, tmp_path / "out", on_asset=ended.append)
    assert report["counts"]["baked"] == 1 and report["counts"]["failed"] == 1
    assert sorted(a["name"] for a in ended) == ["broken", "marble"]
    broken = next(a for a in ended if a["name"] == "broken")
    assert "missing.gltf" in broken["error"]["message"]
    again = sssbake.batch(manifest, tmp_path / "out")
    assert again["counts"]["skipped"] == 1
    assert os.path.exists(tmp_path / "out" / "batch.json")
