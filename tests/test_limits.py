"""Work is bounded up front: the plan estimates a bake's memory and work from the scene and
the request, the estimate holds the memory the bake really takes, and a request over a
limit is refused before anything is allocated or written, naming what drives it."""

import json
import subprocess
import sys

import pytest
from conftest import ROOT, run

EXAMPLES = ROOT / "examples"

# A fresh Python starts the bake as its only child, so the peak it reports is the bake's.
PEAK = """
import json, resource, subprocess, sys
child = subprocess.run(sys.argv[1:], capture_output=True, text=True)
peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024
print(json.dumps({"code": child.returncode, "stderr": child.stderr, "peak": peak}))
"""


def measured(*command: str) -> dict:
    """The exit code, the error output and the peak resident memory (bytes) of `command`."""
    out = subprocess.run([sys.executable, "-c", PEAK, *command], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def planned_bytes(sssbake, *args: str) -> float:
    result = run(sssbake, "plan", *args, "--json")
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)["cost"]["memory_bytes"]


@pytest.mark.parametrize(
    ("asset", "args"),
    [
        ("head/head.gltf", ["--resolution", "512"]),
        ("marble/marble.gltf", ["--resolution", "512", "--method", "octree"]),
        ("ear/ear.gltf", ["--resolution", "768", "--method", "importance", "--samples", "8"]),
        # The empirical model's oblique kernel holds the light split by incidence.
        ("head/head.gltf", ["--resolution", "128", "--model", "empirical", "--method", "brute"]),
    ],
)
def test_the_planned_memory_holds_the_bakes_peak(sssbake, tmp_path, asset, args):
    scene = str(EXAMPLES / asset)
    planned = planned_bytes(sssbake, scene, *args)
    bake = measured(str(sssbake), "bake", scene, "--out", str(tmp_path), *args)
    assert bake["code"] == 0, bake["stderr"]
    assert bake["peak"] <= planned <= 2.5 * bake["peak"], (bake["peak"], planned)


def test_a_resolution_no_memory_holds_is_refused_before_it_is_allocated(sssbake, tmp_path):
    out = tmp_path / "maps"
    scene = str(EXAMPLES / "marble" / "marble.gltf")
    result = measured(str(sssbake), "bake", scene, "--out", str(out), "--resolution", "16384")
    assert result["code"] == 1
    message = result["stderr"]
    assert "max_memory" in message and "16384²" in message and "raise the limit (--max-memory)" in message
    assert not out.exists()
    # Refused from the estimate, not found out by allocating: the process stays small.
    assert result["peak"] < 200 << 20


def test_a_limit_the_user_lowers_refuses_and_names_the_method(sssbake, tmp_path):
    out = tmp_path / "maps"
    scene = str(EXAMPLES / "marble" / "marble.gltf")
    result = run(sssbake, "bake", scene, "--out", str(out), "--method", "brute", "--max-evaluations", "1e9")
    assert result.returncode == 1
    assert "max_evaluations" in result.stderr and "`Ball`" in result.stderr and "brute" in result.stderr
    assert "raise the limit (--max-evaluations)" in result.stderr
    assert not out.exists()
    # Raised, the same request is planned.
    assert run(sssbake, "plan", scene, "--method", "brute", "--max-evaluations", "1e13").returncode == 0
    # A size that is none is refused as the flag's value, before the scene is read.
    bad = run(sssbake, "plan", scene, "--max-memory", "12 parsecs")
    assert bad.returncode == 2 and "`parsecs`" in bad.stderr and "--max-memory" in bad.stderr


def test_a_batch_asset_over_its_limit_fails_alone(sssbake, tmp_path):
    manifest = tmp_path / "batch.toml"
    manifest.write_text(
        f"""
[defaults]
resolution = 64
outputs = ["subsurface"]

[assets.small]
scene = "{EXAMPLES / "head" / "head.gltf"}"

[assets.large]
scene = "{EXAMPLES / "marble" / "marble.gltf"}"
resolution = 16384
"""
    )
    result = run(sssbake, "batch", str(manifest), "--out", str(tmp_path / "out"))
    assert result.returncode == 5, result.stderr
    report = json.loads((tmp_path / "out" / "batch.json").read_text())
    status = {a["name"]: a for a in report["assets"]}
    assert status["small"]["status"] == "baked"
    assert status["large"]["error"]["kind"] == "setting"
    assert "max_memory" in status["large"]["error"]["message"]
