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


@pytest.fixture(scope="module")
def exact(sssbake, tmp_path_factory):
    """The head's exact sum at 256², baked once for every comparison."""
    accuracy, exact = subsurface(sssbake, tmp_path_factory.mktemp("brute"), "--method", "brute")
    assert accuracy["method"] == "brute" and accuracy["estimated_error"] == 0.0
    return exact


def true_error(got, exact):
    covered = exact.max(axis=-1) > 0
    return np.sqrt(((got[covered] - exact[covered]) ** 2).sum() / (exact[covered] ** 2).sum())


@pytest.mark.parametrize("method", ["texture", "octree", "importance"])
def test_the_reported_error_is_the_error_against_the_exact_sum(sssbake, tmp_path, exact, method):
    accuracy, got = subsurface(sssbake, tmp_path, "--method", method)
    assert accuracy["method"] == method and accuracy["tolerance"] is None and not accuracy["set_aside"]
    estimate, truth = accuracy["estimated_error"], true_error(got, exact)
    assert accuracy["texels_checked"] >= 64
    assert truth / 1.5 <= estimate <= truth * 1.5, (method, estimate, truth)


@pytest.mark.parametrize("tolerance", [0.01, 0.003])
def test_auto_holds_the_head_to_its_tolerance_without_the_exact_sum(sssbake, tmp_path, exact, tolerance):
    """The head's exact sum at 256² is over `auto`'s budget, so it must meet the tolerance
    with the octree (refining its threshold at the tighter one), and what it reports is
    the error it has."""
    accuracy, got = subsurface(sssbake, tmp_path, "--tolerance", str(tolerance))
    assert accuracy["tolerance"] == tolerance and accuracy["method"] == "octree"
    estimate, truth = accuracy["estimated_error"], true_error(got, exact)
    assert 0 < estimate <= tolerance
    assert truth / 1.5 <= estimate <= truth * 1.5, (tolerance, estimate, truth)
    final = (accuracy["method"], accuracy["octree_epsilon"])
    for aside in accuracy["set_aside"]:
        assert aside["estimated_error"] > tolerance and (aside["method"], aside["octree_epsilon"]) != final
    # A pilot at a few texels predicted the octree's error first; a predicted miss refined
    # the threshold before the whole map, so the piloted threshold never ran whole.
    pilot = accuracy["pilot"]
    assert pilot["method"] == "octree" and pilot["texels"] >= 64
    # It refines a little below the tolerance: the map's raised light misses by a little more.
    assert 0.5 * tolerance < pilot["refine_above"] < tolerance
    assert pilot["refined"] == (pilot["predicted_error"] > pilot["refine_above"])
    if pilot["refined"]:
        assert accuracy["octree_epsilon"] < pilot["octree_epsilon"]
        assert all(aside["octree_epsilon"] != pilot["octree_epsilon"] for aside in accuracy["set_aside"])


def test_the_pilot_predicts_the_error_of_the_octree_it_pilots(sssbake, tmp_path, exact):
    """The pilot's prediction is the error the piloted octree makes over the whole map."""
    accuracy, _ = subsurface(sssbake, tmp_path / "auto", "--tolerance", "0.001")
    pilot = accuracy["pilot"]
    assert pilot["refined"], pilot
    epsilon = str(pilot["octree_epsilon"])
    _, got = subsurface(sssbake, tmp_path / "octree", "--method", "octree", "--octree-epsilon", epsilon)
    truth = true_error(got, exact)
    assert truth / 1.5 <= pilot["predicted_error"] <= truth * 1.5, (pilot, truth)


def test_auto_takes_the_thin_ear_to_a_3d_sum_and_meets_its_tolerance(sssbake, tmp_path):
    """Texture-space blurs cannot carry the light crossing the ear (most of it at skin's
    reach): `auto` sees that in the geometry and never runs them, at a resolution where the
    reach alone would allow them; the octree refines its threshold once before the exact
    sum."""
    ear = ROOT / "examples" / "ear" / "ear.gltf"
    summary = bake_summary(sssbake, ear, tmp_path, "--resolution", "192", "--outputs", "subsurface")
    (obj,) = summary["objects"]
    assert obj["integrator"]["method"] == "octree" and "thinner" in obj["integrator"]["reason"]
    accuracy = obj["accuracy"]
    assert accuracy["method"] in ("octree", "brute")
    assert accuracy["estimated_error"] <= accuracy["tolerance"] == 0.01
    assert all(aside["method"] == "octree" for aside in accuracy["set_aside"])


@pytest.mark.parametrize("method", ["brute", "octree", "texture", "importance"])
def test_a_three_layer_skin_bakes_the_head_with_every_method(sssbake, tmp_path, method):
    """A 0.014 mm epidermis once asked for 167 million sample points: every method now
    gathers from at most the texels, finishes with a finite map, and says how far it is from
    the exact sum."""
    summary = bake_summary(
        sssbake,
        HEAD,
        tmp_path,
        "--resolution",
        "256",
        "--outputs",
        "subsurface",
        "--preset",
        "skin3layer",
        "--method",
        method,
    )
    (head,) = summary["objects"]
    assert head["sources"] <= head["texels"]
    assert head["accuracy"]["method"] == method
    # Texture space and Monte Carlo are far off this profile (about 15% here), and say so;
    # the 3-D sums are not.
    error = head["accuracy"]["estimated_error"]
    assert 0 <= error < (0.01 if method in ("brute", "octree") else 1.0), head["accuracy"]
    subsurface_map = exr(tmp_path / "Head_subsurface.exr")[..., :3]
    assert np.isfinite(subsurface_map).all() and subsurface_map.max() > 0
