"""The Python side works: bpy and usd-core import and run, and the sssbake
binary answers with numbers an independent Python computation agrees with."""

import json
import math

import numpy as np
from conftest import run


def test_bpy_runs_headless():
    import bpy

    assert bpy.app.version[:2] == (5, 0)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_monkey_add()
    suzanne = bpy.context.active_object
    assert len(suzanne.data.polygons) == 500


def test_usd_core_writes_and_reads_a_stage(tmp_path):
    from pxr import Usd, UsdGeom

    path = tmp_path / "stage.usda"
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageMetersPerUnit(stage, 0.001)
    UsdGeom.Xform.Define(stage, "/root")
    stage.GetRootLayer().Save()
    reopened = Usd.Stage.Open(str(path))
    assert UsdGeom.GetStageMetersPerUnit(reopened) == 0.001
    assert reopened.GetPrimAtPath("/root").IsValid()


def fresnel(cos_i, eta):
    """Unpolarised Fresnel reflectance from inside a medium of relative index eta."""
    sin2_t = eta * eta * (1.0 - cos_i * cos_i)
    if sin2_t >= 1.0:
        return 1.0
    cos_t = math.sqrt(1.0 - sin2_t)
    rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    return 0.5 * (rs * rs + rp * rp)


def dipole_total(sigma_a, sigma_s_reduced, eta):
    """Closed-form dipole total, with F_dr integrated here by brute force."""
    mu = np.linspace(0.0, 1.0, 400_001)
    integrand = np.array([fresnel(m, eta) for m in mu]) * 2.0 * mu
    fdr = float(np.sum((integrand[1:] + integrand[:-1]) * 0.5 * np.diff(mu)))
    a = (1.0 + fdr) / (1.0 - fdr)
    albedo = sigma_s_reduced / (sigma_a + sigma_s_reduced)
    s = math.sqrt(3.0 * (1.0 - albedo))
    return 0.5 * albedo * (1.0 + math.exp(-4.0 / 3.0 * a * s)) * math.exp(-s)


def test_the_binary_agrees_with_an_independent_dipole(sssbake):
    result = run(sssbake, "profile", "--preset", "skin1", "--json")
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["model"] == "dipole"
    # Jensen et al. 2001, skin1: sigma_a and sigma_s' in 1/mm, eta 1.3.
    coefficients = [(0.032, 0.74), (0.17, 0.88), (0.48, 1.01)]
    for channel, (sigma_a, sigma_s) in enumerate(coefficients):
        expected = dipole_total(sigma_a, sigma_s, 1.3)
        assert math.isclose(report["total_reflectance"][channel], expected, rel_tol=1e-6)


def test_the_binary_reports_bad_input(sssbake):
    result = run(sssbake, "profile", "--preset", "no-such-thing")
    assert result.returncode == 1
    assert "unknown preset `no-such-thing`" in result.stderr
