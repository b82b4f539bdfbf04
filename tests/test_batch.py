"""`sssbake batch`: every asset in its own folder, unchanged assets skipped by
their content hash, a changed material file rebaking only its asset, and a
broken asset failing alone, named in the report and in the exit code."""

import json
import os
import pathlib
import shutil

import pytest
from conftest import ROOT, run

# Exit code of a batch in which some assets failed (docs/pipelines.md).
SOME_FAILED = 5

# The examples at 64² (cheap); head and head_usd are the same head, with the
# same file stem and object name, from two formats.
MANIFEST = """
[defaults]
resolution = 64
outputs = ["subsurface", "irradiance", "diffuse"]

[assets.head]
scene = "head/head.gltf"
material = "materials/skin_two_layer.toml"

[assets.head_usd]
scene = "head/head.usda"

[assets.marble]
scene = "marble/marble.gltf"

[assets.ear]
scene = "ear/ear.gltf"
preset = "skin1"
"""


def examples(tmp_path: pathlib.Path) -> pathlib.Path:
    """A copy of the examples (so a test can change one) with the manifest."""
    folder = tmp_path / "assets"
    shutil.copytree(ROOT / "examples", folder, ignore=shutil.ignore_patterns("*.py"))
    (folder / "batch.toml").write_text(MANIFEST)
    return folder


def batch(sssbake, manifest, out, *extra):
    result = run(sssbake, "batch", str(manifest), "--out", str(out), "--json", *extra)
    report = json.loads(result.stdout) if result.stdout.strip() else None
    return result, report


def statuses(report) -> dict:
    return {asset["name"]: asset["status"] for asset in report["assets"]}


def stamps(folder: pathlib.Path) -> dict:
    """Every output file's bytes and modification time."""
    return {
        p.relative_to(folder): (p.read_bytes(), p.stat().st_mtime_ns)
        for p in sorted(folder.rglob("*"))
        if p.is_file() and "reports" not in p.parts and p.name != "batch.json"
    }


@pytest.fixture(scope="module")
def first_run(sssbake, tmp_path_factory):
    folder = examples(tmp_path_factory.mktemp("batch"))
    out = folder.parent / "out"
    result, report = batch(sssbake, folder / "batch.toml", out, "--jobs", "2")
    assert result.returncode == 0, result.stderr
    return folder, out, report


def test_every_asset_gets_its_own_folder_even_with_the_same_stem_and_object(first_run):
    _, out, report = first_run
    assert statuses(report) == dict.fromkeys(["ear", "head", "head_usd", "marble"], "baked")
    assert report["counts"] == {"baked": 4, "skipped": 0, "failed": 0, "missing": 0}
    assert report["jobs"] == min(2, os.cpu_count())
    gltf = (out / "head" / "Head_subsurface.exr").read_bytes()
    usd = (out / "head_usd" / "Head_subsurface.exr").read_bytes()
    assert gltf != usd, "two materials, two maps, two folders"
    assert (out / "head" / "head.gltf").exists() and (out / "head_usd" / "head_sssbake.usda").exists()
    for asset in report["assets"]:
        assert asset["error"] is None and asset["seconds"] > 0
        assert len(asset["hash"]) == 32
        files = {pathlib.Path(f).name for f in asset["files"]}
        assert {"sssbake-inputs.json"} < files
        assert all(pathlib.Path(f).exists() for f in asset["files"])
        own = json.loads((out / "reports" / f"{asset['name']}.json").read_text())
        assert own == asset, "the asset's report is the batch's entry"
        assert own["summary"]["resolution"] == 64
    assert json.loads((out / "batch.json").read_text()) == report
    assert not [p for p in out.iterdir() if p.name.startswith(".")], "no staging left"


def test_the_record_lists_what_the_bake_read(first_run):
    folder, out, _ = first_run
    gltf = json.loads((out / "head" / "sssbake-inputs.json").read_text())
    assert {pathlib.Path(f).resolve() for f in gltf["files"]} == {
        (folder / p).resolve() for p in ("head/head.gltf", "head/head.bin", "materials/skin_two_layer.toml")
    }
    usd = json.loads((out / "head_usd" / "sssbake-inputs.json").read_text())
    assert [pathlib.Path(f).resolve() for f in usd["files"]] == [(folder / "head/head.usda").resolve()]


def test_a_second_run_skips_everything_and_a_changed_material_rebakes_only_its_asset(sssbake, tmp_path):
    folder = examples(tmp_path)
    out = tmp_path / "out"
    assert batch(sssbake, folder / "batch.toml", out)[0].returncode == 0
    before = stamps(out)

    result, report = batch(sssbake, folder / "batch.toml", out)
    assert result.returncode == 0, result.stderr
    assert set(statuses(report).values()) == {"skipped"}
    assert stamps(out) == before, "nothing written"

    material = folder / "materials" / "skin_two_layer.toml"
    material.write_text(
        material.read_text().replace("sigma_a = [0.6, 1.0, 2.2]", "sigma_a = [0.9, 1.0, 2.2]")
    )
    result, report = batch(sssbake, folder / "batch.toml", out)
    assert result.returncode == 0, result.stderr
    assert statuses(report) == {"ear": "skipped", "head": "baked", "head_usd": "skipped", "marble": "skipped"}
    after = stamps(out)
    changed = {str(p.parent) for p in after if after[p] != before.get(p)}
    assert changed == {"head"}
    assert (
        after[pathlib.Path("head/Head_subsurface.exr")][0]
        != before[pathlib.Path("head/Head_subsurface.exr")][0]
    )

    result, report = batch(sssbake, folder / "batch.toml", out, "--force")
    assert result.returncode == 0
    assert set(statuses(report).values()) == {"baked"}


def test_a_broken_asset_fails_alone_named_in_the_report_and_the_exit_code(sssbake, tmp_path):
    folder = examples(tmp_path)
    manifest = folder / "batch.toml"
    manifest.write_text(
        MANIFEST
        + '\n[assets.missing]\nscene = "nowhere/lost.gltf"\n'
        + '\n[assets.bad_preset]\nscene = "marble/marble.gltf"\npreset = "granite"\n'
    )
    out = tmp_path / "out"
    result, report = batch(sssbake, manifest, out)
    assert result.returncode == SOME_FAILED, result.stderr
    assert report["counts"] == {"baked": 4, "skipped": 0, "failed": 2, "missing": 0}
    failed = {a["name"]: a for a in report["assets"] if a["status"] == "failed"}
    assert set(failed) == {"missing", "bad_preset"}
    assert failed["missing"]["error"]["kind"] == "input"
    assert "lost.gltf" in failed["missing"]["error"]["message"]
    assert "granite" in failed["bad_preset"]["error"]["message"]
    for name in failed:
        assert not (out / name).exists(), "a failed asset leaves no folder"
        assert json.loads((out / "reports" / f"{name}.json").read_text())["status"] == "failed"
    assert "missing: failed (input)" in result.stderr
    assert not [p for p in out.iterdir() if p.name.startswith(".")], "no staging left"


def test_a_manifest_with_an_unknown_key_is_refused_naming_it(sssbake, tmp_path):
    manifest = tmp_path / "batch.toml"
    manifest.write_text('[assets.head]\nscene = "h.gltf"\nresolutoin = 64\n')
    result, _ = batch(sssbake, manifest, tmp_path / "out")
    assert result.returncode == 1
    assert "assets.head" in result.stderr and "resolutoin" in result.stderr
    assert not (tmp_path / "out").exists()


def test_an_asset_folder_that_holds_its_own_input_is_refused_and_the_input_kept(sssbake, tmp_path):
    folder = examples(tmp_path)
    before = {p: p.read_bytes() for p in (folder / "head").iterdir()}
    # Baked into the assets' own folder, the asset `head` would replace head/.
    result, report = batch(sssbake, folder / "batch.toml", folder, "--asset", "head")
    assert result.returncode == SOME_FAILED
    (head,) = report["assets"]
    assert head["error"]["kind"] == "output" and "holds the asset's input" in head["error"]["message"]
    assert {p: p.read_bytes() for p in (folder / "head").iterdir()} == before
    # A folder the batch did not make is not replaced either.
    out = tmp_path / "out"
    (out / "marble").mkdir(parents=True)
    (out / "marble" / "notes.txt").write_text("mine")
    result, report = batch(sssbake, folder / "batch.toml", out, "--asset", "marble")
    assert result.returncode == SOME_FAILED
    assert "not a batch's folder" in report["assets"][0]["error"]["message"]
    assert sorted(p.name for p in (out / "marble").iterdir()) == ["notes.txt"]
