"""Every integrator gives the same maps, byte for byte, on one thread and on two: work is
split into parts whose results do not depend on which thread ran them."""

import pytest
from conftest import ROOT, run

SCENE = ROOT / "examples" / "ear" / "ear.gltf"


@pytest.mark.parametrize("method", ["brute", "octree", "texture", "importance"])
def test_one_thread_and_two_give_the_same_bytes(sssbake, tmp_path, method):
    maps = {}
    for threads in ("1", "2"):
        out = tmp_path / threads
        args = ["bake", str(SCENE), "--out", str(out), "--resolution", "96", "--method", method]
        result = run(sssbake, *args, "--threads", threads, "--samples", "8")
        assert result.returncode == 0, result.stderr
        maps[threads] = {path.name: path.read_bytes() for path in sorted(out.glob("*.exr"))}
    assert maps["1"] and maps["1"].keys() == maps["2"].keys()
    for name, data in maps["1"].items():
        assert data == maps["2"][name], f"{method}: {name} differs between 1 and 2 threads"
