"""Every bake says how far it is from the exact sum: the estimate a bake reports (the exact
sum at a random subset of texels) agrees with the error measured against a full exact bake,
on the bundled head with its own skin."""

import numpy as np
import pytest
from conftest import ROOT, bake_summary, exr

HEAD = ROOT / "examples" / "head" / "head.gltf"


def subsurface(sssbake, out, *args):
    summary = bake_summary(sssbake, HEAD, out, "--resolution", "256", "--outputs", "subsurface", *args)
    (head,) = summary["objects"]
    return head["accuracy"], exr(out / "Head_subsurface.exr")[..., :3]


@pytest.mark.parametrize("method", ["texture", "octree", "importance"])
def test_the_reported_error_is_the_error_against_the_exact_sum(sssbake, tmp_path, method):
    exact_accuracy, exact = subsurface(sssbake, tmp_path / "brute", "--method", "brute")
    assert exact_accuracy["method"] == "brute" and exact_accuracy["estimated_error"] == 0.0
    accuracy, got = subsurface(sssbake, tmp_path / method, "--method", method)
    assert accuracy["method"] == method and accuracy["tolerance"] is None and not accuracy["set_aside"]
    covered = exact.max(axis=-1) > 0
    true_error = np.sqrt(((got[covered] - exact[covered]) ** 2).sum() / (exact[covered] ** 2).sum())
    estimate = accuracy["estimated_error"]
    assert accuracy["texels_checked"] >= 512
    assert true_error / 2 <= estimate <= true_error * 2, (method, estimate, true_error)


def test_auto_holds_every_object_to_its_tolerance(sssbake, tmp_path):
    accuracy, _ = subsurface(sssbake, tmp_path / "auto", "--tolerance", "0.001")
    assert accuracy["tolerance"] == 0.001
    assert accuracy["estimated_error"] <= 0.001
    for aside in accuracy["set_aside"]:
        assert aside["estimated_error"] > 0.001 and aside["method"] != accuracy["method"]
