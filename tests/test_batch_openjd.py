"""`sssbake batch --openjd`: an Open Job Description job bundle that
openjd-model accepts and openjd-cli runs, baking one asset as the batch
would."""

import json
import os
import subprocess
import sys

from conftest import run
from test_batch import batch, examples


def bundle(sssbake, tmp_path):
    folder = examples(tmp_path)
    result = run(sssbake, "batch", str(folder / "batch.toml"), "--openjd", str(tmp_path / "bundle"))
    assert result.returncode == 0, result.stderr
    template = json.loads((tmp_path / "bundle" / "template.json").read_text())
    values = json.loads((tmp_path / "bundle" / "parameter_values.json").read_text())
    return folder, template, {v["name"]: v["value"] for v in values["parameterValues"]}


def test_the_bundle_is_a_valid_job_with_one_task_per_asset(sssbake, tmp_path):
    from openjd.model import create_job, decode_job_template, preprocess_job_parameters

    folder, template_data, values = bundle(sssbake, tmp_path)
    assert values == {"Manifest": str(folder / "batch.toml"), "OutDir": str(folder / "out")}
    template = decode_job_template(template=template_data)
    parameters = preprocess_job_parameters(
        job_template=template,
        job_parameter_values={**values, "SssbakeCommand": str(sssbake)},
        job_template_dir=tmp_path / "bundle",
        current_working_dir=tmp_path,
    )
    job = create_job(job_template=template, job_parameter_values=parameters)
    bake, report = job.steps
    assert (bake.name, report.name) == ("Bake", "Report")
    assert [d.dependsOn for d in report.dependencies] == ["Bake"]
    (asset,) = bake.parameterSpace.taskParameterDefinitions.values()
    assert list(asset.range) == ["ear", "head", "head_usd", "marble"]


def test_openjd_run_bakes_one_asset_as_the_batch_does(sssbake, tmp_path):
    folder, _, values = bundle(sssbake, tmp_path)
    openjd = os.path.join(os.path.dirname(sys.executable), "openjd")
    params = {**values, "SssbakeCommand": str(sssbake)}
    result = subprocess.run(
        [openjd, "run", str(tmp_path / "bundle" / "template.json"), "--step", "Bake"]
        + ["--task-param", "Asset=marble", "--job-param", json.dumps(params)],
        check=False,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    out = folder / "out"
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == ["marble", "reports"]
    report = json.loads((out / "reports" / "marble.json").read_text())
    assert report["status"] == "baked"
    local, local_report = batch(sssbake, folder / "batch.toml", tmp_path / "local", "--asset", "marble")
    assert local.returncode == 0, local.stderr
    for name in ("Ball_subsurface.exr", "Ball_diffuse.png", "marble.gltf"):
        assert (out / "marble" / name).read_bytes() == (tmp_path / "local" / "marble" / name).read_bytes()
    assert local_report["assets"][0]["hash"] == report["hash"]
