"""The glTF copy as the web shows it: each bundled example baked, then drawn in headless
Chromium by a plain three.js page and by model-viewer (its own bundle and defaults) from a
fixed camera, and screenshotted. A second pass draws the same view with each surface
showing its texture coordinates, so every pixel is traced to the texels it shows; the
screenshot must then be the `diffuse` map's radiance through the viewer's documented
pipeline (emissive texture decoded from sRGB, times the strength; exposure, tone mapping,
the sRGB output transfer), with nothing added by the lights the file carries or by
model-viewer's environment light.

Chromium comes from Debian's packages and three.js, model-viewer and playwright-core from
the npm registry (scripts/install-test-deps.sh); without them these tests are skipped,
except under CI, where they must run."""

import json
import math
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest
from conftest import ROOT, bake_summary, exr, png_rgb, srgb_to_linear
from traced_view import assert_shows, nothing_outside, radiance_at, smooth_pixels

RESOLUTION = 256
SIZE = 512
FIELD_OF_VIEW = 30.0
SHOOT = ROOT / "tests" / "viewer" / "shoot.mjs"
NODE_MODULES = ROOT / ".node" / "node_modules"
CHROMIUM = pathlib.Path(os.environ.get("CHROMIUM", "/usr/bin/chromium"))

# Each example from where its light shows: (file, baked object, azimuth θ and polar angle
# φ from +Y of the camera, in radians, as model-viewer's camera-orbit).
EXAMPLES = {
    "head": ("examples/head/head.gltf", "Head", math.pi, 1.0),
    "ear": ("examples/ear/ear.gltf", "Ear", 0.3, 0.6),
    "marble": ("examples/marble/marble.gltf", "Ball", 0.5, 1.0),
}
# model-viewer raises the exposure of its neutral tone mapping under its default
# environment by this factor (`COMMERCE_EXPOSURE` in its Renderer).
MODEL_VIEWER_EXPOSURE_GAIN = 1.3


def missing_browser() -> str | None:
    """Why the browser check cannot run here, or None."""
    if shutil.which("node") is None:
        return "Node.js is not installed"
    if not CHROMIUM.exists():
        return f"Chromium is not at {CHROMIUM} (Debian: apt-get install chromium; or set CHROMIUM)"
    for package in ("three", "@google/model-viewer", "playwright-core"):
        if not (NODE_MODULES / package).exists():
            return f"the npm package {package} is not in .node (run scripts/install-test-deps.sh)"
    return None


@pytest.fixture(scope="module")
def browser():
    reason = missing_browser()
    if reason is not None:
        if os.environ.get("CI"):
            pytest.fail(f"the web viewers' check must run under CI: {reason}")
        pytest.skip(f"web viewers' check skipped: {reason}")


@pytest.fixture(scope="module")
def bakes(sssbake, tmp_path_factory):
    """Each example baked at RESOLUTION²: its output folder and the summary."""
    baked = {}
    for name, (scene, *_) in EXAMPLES.items():
        out = tmp_path_factory.mktemp(f"web-{name}")
        summary = bake_summary(
            sssbake, ROOT / scene, out, "--resolution", str(RESOLUTION), "--light-check", "0"
        )
        baked[name] = (out, summary)
    return baked


def pbr_neutral(colour: np.ndarray) -> np.ndarray:
    """The Khronos PBR Neutral tone mapping (three.js's NeutralToneMapping, model-viewer's
    default), on linear RGB in the last axis."""
    start, desaturation = 0.8 - 0.04, 0.15
    x = colour.min(axis=-1, keepdims=True)
    colour = colour - np.where(x < 0.08, x - 6.25 * x * x, 0.04)
    peak = colour.max(axis=-1, keepdims=True)
    d = 1.0 - start
    new_peak = 1.0 - d * d / (peak + d - start)
    compressed = colour * new_peak / np.maximum(peak, 1e-12)
    g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0)
    compressed = compressed * (1.0 - g) + new_peak * g
    return np.where(peak < start, colour, compressed)


def shoot(viewer: str, out: pathlib.Path, name: str, exposure: float, tmp_path: pathlib.Path) -> dict:
    """Runs tests/viewer/shoot.mjs for one viewer; returns the screenshot (linear display
    values, rows top to bottom), the texture coordinates and coverage of the uv pass, and
    the page's report."""
    _, _, theta, phi = EXAMPLES[name]
    copy = json.loads((out / f"{name}.gltf").read_text())
    low, high = np.array(copy["accessors"][0]["min"]), np.array(copy["accessors"][0]["max"])
    half_diagonal = float(np.linalg.norm(high - low)) / 2
    (material,) = [m for m in copy["materials"] if m["name"].endswith("(sssbake)")]
    texcoord = material["emissiveTexture"].get("texCoord", 0)
    view = {
        "viewer": viewer,
        "asset": str(out / f"{name}.gltf"),
        "size": SIZE,
        "orbit": {
            "theta": theta,
            "phi": phi,
            "radius": 0.9 * half_diagonal / math.sin(math.radians(FIELD_OF_VIEW / 2)),
        },
        "target": ((low + high) / 2).tolist(),
        "fov": FIELD_OF_VIEW,
        "toneMapping": "linear",
        "exposure": exposure,
        "uvAttribute": "uv" if texcoord == 0 else f"uv{texcoord}",
    }
    view_file = tmp_path / f"{viewer}-{name}.json"
    view_file.write_text(json.dumps(view))
    prefix = tmp_path / f"{viewer}-{name}"
    result = subprocess.run(
        ["node", str(SHOOT), str(view_file), str(prefix)],
        capture_output=True,
        text=True,
        check=False,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr
    look = srgb_to_linear(png_rgb(pathlib.Path(f"{prefix}_look.png")) / 255)
    uv = np.fromfile(f"{prefix}_uv.f32", dtype=np.float32).reshape(SIZE, SIZE, 4)[::-1].astype(np.float64)
    report = json.loads(pathlib.Path(f"{prefix}.json").read_text())
    return {"look": look, "uv": uv[..., :2], "covered": uv[..., 3] > 0.5, "report": report}


@pytest.mark.parametrize("viewer", ["three", "model-viewer"])
@pytest.mark.parametrize("name", list(EXAMPLES))
def test_a_web_viewer_shows_the_baked_radiance(browser, bakes, viewer, name, tmp_path):
    out, _ = bakes[name]
    (_, object_name) = EXAMPLES[name][:2]
    diffuse = exr(out / f"{object_name}_diffuse.exr").astype(np.float64)
    # The exposure that puts the brightest texel at display white.
    exposure = 1.0 / float(diffuse.max())
    shot = shoot(viewer, out, name, exposure, tmp_path)
    look, uv, covered, report = shot["look"], shot["uv"], shot["covered"], shot["report"]
    # The file's lights are in the scene: light falling on the surface would show.
    assert report["lights"] >= 1

    # What the viewer's pipeline makes of the map at each covered pixel.
    radiance = radiance_at(diffuse, uv, covered)
    if viewer == "three":
        expected = np.clip(exposure * radiance, 0, 1)
    else:
        assert report["toneMapping"] == "auto" and report["environment"] is None
        expected = pbr_neutral(exposure * MODEL_VIEWER_EXPOSURE_GAIN * radiance)
    # Bright enough that one 8-bit step of the sRGB output is under 2%.
    chosen = smooth_pixels(expected, covered, uv, diffuse) & (expected > 0.2)
    assert_shows(look, expected, chosen)
    assert nothing_outside(look, covered)
