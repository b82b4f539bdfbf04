"""A large asset on the farm, one task per object and an assembly: the
assembled folder equals a local whole-asset bake bit for bit, a worker
killed mid object-task has its task run again, a failed object is named in
the asset's report, and the assembly refuses a missing or stale part."""

import json
import os
import pathlib
import signal
import threading
import time

import pytest
from conftest import run
from test_batch import SOME_FAILED, batch, examples
from test_batch_farm import farm, maps

# The ear with a second, smaller shell ("Lobe") 1 cm behind it: two objects
# that shadow each other under the ear's two lights; in glTF, and in USD as a
# layer over the ear's stage referencing the ear a second time.
MANIFEST = """
[defaults]
resolution = 32
outputs = ["subsurface", "irradiance", "diffuse"]

[assets.pair]
scene = "ear/pair.gltf"
preset = "skin1"

[assets.marble]
scene = "marble/marble.gltf"
"""


PAIR_USD = """
[assets.pair_usd]
scene = "ear/pair.usda"
preset = "skin1"
"""

PAIR_USDA = """#usda 1.0
(
    defaultPrim = "root"
    metersPerUnit = 1
    upAxis = "Z"
    subLayers = [@./ear.usda@]
)

over "root"
{
    def Xform "Lobe" (
        prepend references = @./ear.usda@</root/Ear>
    )
    {
        double3 xformOp:translate = (0, -0.01, 0)
        float3 xformOp:scale = (0.5, 1, 0.5)
        uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:scale"]
    }
}
"""


def pair_assets(tmp_path, manifest=MANIFEST):
    folder = examples(tmp_path)
    gltf = json.loads((folder / "ear" / "ear.gltf").read_text())
    gltf["nodes"].append({"mesh": 0, "name": "Lobe", "translation": [0, -0.01, 0], "scale": [0.5, 1, 0.5]})
    gltf["scenes"][0]["nodes"].append(len(gltf["nodes"]) - 1)
    (folder / "ear" / "pair.gltf").write_text(json.dumps(gltf))
    (folder / "ear" / "pair.usda").write_text(PAIR_USDA)
    (folder / "batch.toml").write_text(manifest)
    return folder / "batch.toml"


def hidden(out):
    """Every hidden file or folder left anywhere in `out`."""
    return sorted(str(p.relative_to(out)) for p in out.rglob(".*"))


def processes_writing_to(out):
    """The running processes whose command line names `out` (Linux)."""
    found = []
    for process in pathlib.Path("/proc").glob("[0-9]*"):
        try:
            command = (process / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if str(out) in command:
            found.append(command)
    return found


def summary_without_timings(report):
    """An asset report's summary without what differs between two bakes of
    the same inputs: seconds and the staging folders' paths."""
    summary = dict(report["summary"], files=None, write_seconds=None)
    summary["objects"] = [
        dict(o, seconds=None, accuracy=without_seconds(o["accuracy"])) for o in summary["objects"]
    ]
    return summary


def without_seconds(accuracy):
    """An object's accuracy without the seconds its check against light took."""
    if not accuracy or not accuracy.get("light"):
        return accuracy
    return dict(accuracy, light=dict(accuracy["light"], seconds=None))


def test_an_asset_of_several_objects_is_split_when_large_or_asked(sssbake, tmp_path):
    manifest = pair_assets(tmp_path)
    tasks = json.loads(run(sssbake, "batch", str(manifest), "--tasks", "--split-above", "0").stdout)
    assert [(t["asset"], t["objects"]) for t in tasks] == [("marble", []), ("pair", ["Ear", "Lobe"])]
    assert all(t["work"] > 0 for t in tasks)
    # At 32² the pair is far below the default threshold: one task.
    default = json.loads(run(sssbake, "batch", str(manifest), "--tasks").stdout)
    assert [t["objects"] for t in default] == [[], []]
    # The manifest decides where it says so: always for the pair, never for the marble.
    manifest.write_text(
        MANIFEST.replace('preset = "skin1"', 'preset = "skin1"\nsplit = "objects"').replace(
            'marble.gltf"', 'marble.gltf"\nsplit = "whole"'
        )
    )
    asked = json.loads(run(sssbake, "batch", str(manifest), "--tasks", "--split-above", "inf").stdout)
    assert [t["objects"] for t in asked] == [[], ["Ear", "Lobe"]]
    manifest.write_text(MANIFEST.replace('preset = "skin1"', 'preset = "skin1"\nsplit = "whole"'))
    whole = json.loads(run(sssbake, "batch", str(manifest), "--tasks", "--split-above", "0").stdout)
    assert [t["objects"] for t in whole] == [[], []]


def test_a_split_asset_on_the_cluster_equals_a_local_whole_bake(sssbake, client, tmp_path):
    manifest = pair_assets(tmp_path, MANIFEST + PAIR_USD)
    out = tmp_path / "farm"
    report = farm.run(manifest, out, client, sssbake=str(sssbake), threads_per_task=1, split_above=0)
    assert report["counts"] == {"baked": 3, "skipped": 0, "failed": 0, "missing": 0}
    local, local_report = batch(sssbake, manifest, tmp_path / "local")
    assert local.returncode == 0, local.stderr
    farm_files, local_files = maps(out), maps(tmp_path / "local")
    for asset, look in [("pair", "pair.gltf"), ("pair_usd", "pair_sssbake.usda")]:
        files = sorted(str(p.relative_to(asset)) for p in farm_files if p.parts[0] == asset)
        assert len([f for f in files if f.endswith(".exr")]) == 2 * 3, files
        assert look in files
    assert "Lobe_diffuse_emissive.png" in os.listdir(out / "pair")
    # Every map, preview, the glTF copy, the USD layer and the inputs record, byte for byte.
    assert farm_files == local_files
    assert hidden(out) == [], "no parts or staging folders left"
    for farm_asset, local_asset in zip(report["assets"], local_report["assets"], strict=True):
        assert farm_asset["hash"] == local_asset["hash"]
        assert summary_without_timings(farm_asset) == summary_without_timings(local_asset)
    # A second run skips the assembled assets: their record is the whole bake's.
    again = farm.run(manifest, out, client, sssbake=str(sssbake), threads_per_task=1, split_above=0)
    assert again["counts"]["skipped"] == 3
    assert hidden(out) == []


def test_a_worker_killed_mid_object_task_has_it_run_again(sssbake, client, tmp_path):
    # The exact sum at 96²: the ear's task takes seconds (skin's reach), long enough to catch.
    slow = MANIFEST.replace("resolution = 32", 'resolution = 96\nmethod = "brute"')
    manifest = pair_assets(tmp_path, slow.split("[assets.marble]")[0])
    out = tmp_path / "farm"
    killed = []

    def kill_the_worker_baking_the_ear():
        pids = client.run(os.getpid)
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and not killed:
            if any((out / ".parts" / "pair").glob(".Ear.partial-*")):
                for worker, keys in client.processing().items():
                    if any(str(k).startswith("sssbake-pair/object-0") for k in keys) and worker in pids:
                        os.kill(pids[worker], signal.SIGKILL)
                        killed.append(worker)
                        return
            time.sleep(0.02)

    killer = threading.Thread(target=kill_the_worker_baking_the_ear)
    killer.start()
    report = farm.run(manifest, out, client, sssbake=str(sssbake), threads_per_task=1, split_above=0)
    killer.join()
    assert killed, "the ear's worker was killed mid-bake"
    assert processes_writing_to(out) == [], "the killed task's bake died with its worker"
    assert report["counts"] == {"baked": 1, "skipped": 0, "failed": 0, "missing": 0}
    pair = json.loads((out / "reports" / "pair.json").read_text())
    assert pair["status"] == "baked" and all(os.path.exists(f) for f in pair["files"])
    local, _ = batch(sssbake, manifest, tmp_path / "local")
    assert local.returncode == 0, local.stderr
    assert maps(out / "pair") == maps(tmp_path / "local" / "pair")
    assert hidden(out) == [], "the killed task's staging folder went with the parts"


def test_a_failed_object_fails_its_asset_naming_it_and_keeps_the_other_parts(sssbake, client, tmp_path):
    manifest = pair_assets(tmp_path)
    out = tmp_path / "farm"
    # A file where the lobe's part goes: its bake cannot be moved into place.
    (out / ".parts" / "pair").mkdir(parents=True)
    (out / ".parts" / "pair" / "Lobe").write_text("in the way")
    report = farm.run(manifest, out, client, sssbake=str(sssbake), threads_per_task=1, split_above=0)
    assert report["counts"] == {"baked": 1, "skipped": 0, "failed": 1, "missing": 0}
    pair = next(a for a in report["assets"] if a["name"] == "pair")
    assert pair["status"] == "failed"
    message = pair["error"]["message"]
    assert "asset `pair`" in message and "object `Lobe`" in message, message
    assert "cannot move the bake into place" in message, message
    assert not (out / "pair").exists(), "no half-assembled folder"
    assert (out / ".parts" / "pair" / "Ear" / "Ear_subsurface.exr").exists(), "the ear's part is kept"
    lobe = json.loads((out / ".parts" / "pair" / "Lobe.json").read_text())
    assert lobe["status"] == "failed" and lobe["error"]["kind"] == "output"
    # The shell's exit code says so too.
    assembled, _ = batch(sssbake, manifest, out, "--asset", "pair", "--assemble")
    assert assembled.returncode == SOME_FAILED


@pytest.mark.parametrize("case", ["missing", "stale"])
def test_the_assembly_refuses_a_missing_or_stale_part_naming_the_object(sssbake, tmp_path, case):
    manifest = pair_assets(tmp_path)
    out = tmp_path / "out"
    for obj in ["Ear"] if case == "missing" else ["Ear", "Lobe"]:
        baked, part = batch(sssbake, manifest, out, "--asset", "pair", "--object", obj)
        assert baked.returncode == 0 and part["status"] == "baked", baked.stderr
    if case == "stale":
        manifest.write_text(manifest.read_text().replace('preset = "skin1"', 'preset = "skin2"'))
    result, report = batch(sssbake, manifest, out, "--asset", "pair", "--assemble")
    assert result.returncode == SOME_FAILED
    message = report["assets"][0]["error"]["message"]
    assert "asset `pair`" in message
    if case == "missing":
        assert "object `Lobe`" in message and "no part" in message, message
    else:
        assert "object `Ear`" in message and "other inputs" in message, message
    assert not (out / "pair").exists()
    assert hidden(out) == [".parts"], "the parts stay, and nothing else"


def test_objects_of_one_name_are_split_by_their_file_stems(sssbake, tmp_path):
    manifest = pair_assets(tmp_path)
    pair = manifest.parent / "ear" / "pair.gltf"
    pair.write_text(pair.read_text().replace('"Lobe"', '"Ear"'))
    tasks = json.loads(run(sssbake, "batch", str(manifest), "--tasks", "--split-above", "0").stdout)
    stems = next(t["objects"] for t in tasks if t["asset"] == "pair")
    assert stems == ["Ear", "Ear.1"]
    out = tmp_path / "out"
    for stem in stems:
        baked, part = batch(sssbake, manifest, out, "--asset", "pair", "--object", stem)
        assert baked.returncode == 0 and part["status"] == "baked", baked.stderr
    assembled, _ = batch(sssbake, manifest, out, "--asset", "pair", "--assemble")
    assert assembled.returncode == 0, assembled.stderr
    local, _ = batch(sssbake, manifest, tmp_path / "local", "--asset", "pair")
    assert local.returncode == 0, local.stderr
    assert maps(out / "pair") == maps(tmp_path / "local" / "pair")
    assert "Ear.1_subsurface.exr" in os.listdir(out / "pair")
