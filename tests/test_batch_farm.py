"""The batch on a Dask cluster (`sssbake.farm`): a LocalCluster of two
worker processes bakes the same maps as a local run, bit for bit, and a worker
killed mid-task has its task run again elsewhere, with a complete report."""

import importlib.util
import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from conftest import ROOT
from test_batch import batch, examples


def load_farm():
    """python/sssbake/farm.py, loaded under a name of its own: the Blender add-on's
    package, which other tests import, is also called `sssbake`."""
    spec = importlib.util.spec_from_file_location("sssbake_farm", ROOT / "python" / "sssbake" / "farm.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


farm = load_farm()
pytest.importorskip("distributed")


def maps(folder):
    """Every file of every asset folder (maps, assets, the inputs record), by path."""
    return {
        p.relative_to(folder): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file() and p.relative_to(folder).parts[0] not in ("reports", "batch.json")
    }


def test_the_farms_maps_equal_a_local_runs_bit_for_bit(sssbake, client, tmp_path):
    folder = examples(tmp_path)
    report = farm.run(
        folder / "batch.toml", tmp_path / "farm", client, sssbake=str(sssbake), threads_per_task=1
    )
    assert report["counts"] == {"baked": 4, "skipped": 0, "failed": 0, "missing": 0}
    assert json.loads((tmp_path / "farm" / "batch.json").read_text()) == report
    local, local_report = batch(sssbake, folder / "batch.toml", tmp_path / "local")
    assert local.returncode == 0, local.stderr
    farm_maps, local_maps = maps(tmp_path / "farm"), maps(tmp_path / "local")
    assert len(farm_maps) >= 4 * 8
    assert farm_maps == local_maps
    assert [a["hash"] for a in report["assets"]] == [a["hash"] for a in local_report["assets"]]


def test_a_worker_killed_mid_task_has_its_task_run_again(sssbake, client, tmp_path):
    folder = examples(tmp_path)
    # One asset slow enough to be caught mid-bake: the exact sum at 128².
    manifest = folder / "batch.toml"
    manifest.write_text(
        manifest.read_text().replace(
            'preset = "skin1"', 'preset = "skin1"\nmethod = "brute"\nresolution = 128'
        )
    )
    out = tmp_path / "farm"
    killed = []

    def kill_the_worker_baking_the_ear():
        pids = client.run(os.getpid)
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and not killed:
            if any(out.glob(".ear.partial-*")):
                for worker, keys in client.processing().items():
                    if any(str(k).startswith("sssbake-ear") for k in keys) and worker in pids:
                        os.kill(pids[worker], signal.SIGKILL)
                        killed.append(worker)
                        return
            time.sleep(0.05)

    killer = threading.Thread(target=kill_the_worker_baking_the_ear)
    killer.start()
    report = farm.run(manifest, out, client, sssbake=str(sssbake), threads_per_task=1)
    killer.join()
    assert killed, "the ear's worker was killed mid-bake"
    assert report["counts"] == {"baked": 4, "skipped": 0, "failed": 0, "missing": 0}
    assert {a["name"] for a in report["assets"]} == {"ear", "head", "head_usd", "marble"}
    ear = json.loads((out / "reports" / "ear.json").read_text())
    assert ear["status"] == "baked"
    assert all(os.path.exists(f) for f in ear["files"])
    # The killed bake's sssbake process may still finish; either way the folder holds
    # one whole bake.
    local, _ = batch(sssbake, manifest, tmp_path / "local", "--asset", "ear")
    assert local.returncode == 0
    assert maps(out / "ear") == maps(tmp_path / "local" / "ear")


def test_python_dash_m_runs_the_installed_farm(tmp_path):
    """`python -m sssbake.farm` is the installed package's own, from any folder."""
    result = subprocess.run(
        [sys.executable, "-m", "sssbake.farm", "--help"],
        check=False,
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    assert "--scheduler" in result.stdout and "sssbake-farm" in result.stdout


def test_the_farm_runs_from_a_shell_against_a_scheduler_address(sssbake, client, tmp_path):
    folder = examples(tmp_path)
    manifest = folder / "batch.toml"
    manifest.write_text('[defaults]\nresolution = 32\n[assets.marble]\nscene = "marble/marble.gltf"\n')
    # The console script the installed package provides, as a user runs it.
    farm_command = Path(sys.executable).with_name("sssbake-farm")
    assert farm_command.is_file(), "pip install . provides the sssbake-farm command"
    result = subprocess.run(
        [str(farm_command), str(manifest)]
        + ["--out", str(tmp_path / "farm"), "--scheduler", client.scheduler.address]
        + ["--sssbake", str(sssbake), "--threads-per-task", "1"],
        check=False,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["counts"]["baked"] == 1
    assert (tmp_path / "farm" / "marble" / "Ball_subsurface.exr").exists()
