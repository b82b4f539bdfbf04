"""`sssbake plan --json` states exactly the decisions `sssbake bake --json` with the
same options follows, on every bundled example in both formats."""

import json
import sys

import pytest
from conftest import ROOT, bake_summary, run

EXAMPLES = [
    ROOT / "examples" / name / f"{name}.{kind}"
    for name in ("head", "marble", "ear")
    for kind in ("gltf", "usda")
]
ENV = {"SSSBAKE_PYTHON": sys.executable}


def decisions(summary):
    """Each object's decisions: the summary's objects less what only a bake measures."""
    return [
        {k: v for k, v in o.items() if k not in ("seconds", "sources", "accuracy")}
        for o in summary["objects"]
    ]


@pytest.mark.parametrize("extra", [(), ("--preset", "skin3layer")], ids=["own-material", "skin3layer"])
@pytest.mark.parametrize("scene", EXAMPLES, ids=lambda p: p.name)
def test_the_plan_states_what_the_bake_does(sssbake, scene, extra, tmp_path):
    options = ["--resolution", "48", "--outputs", "subsurface,diffuse", *extra]
    planned = run(sssbake, "plan", str(scene), "--json", *options, env=ENV)
    assert planned.returncode == 0, planned.stderr
    summary = bake_summary(sssbake, scene, tmp_path / "out", *options)
    plan = json.loads(planned.stdout)
    assert plan["objects"], "the plan bakes something"
    assert decisions(plan) == decisions(summary)
    for key in ("resolution", "outputs", "lights"):
        assert plan[key] == summary[key]
    for planned_object in plan["objects"]:
        assert planned_object["scattering"]["run"]
        assert planned_object["integrator"]["method"] in ("brute", "octree", "texture", "importance")
        if extra:
            assert planned_object["material"]["name"] == "skin3layer"
            assert planned_object["material"]["source"] == "--preset"
        else:
            assert planned_object["material"]["source"].startswith("asset")
