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

import os

import numpy as np
import pytest
from conftest import ROOT, bake_summary, exr
from traced_view import assert_shows, nothing_outside, radiance_at, smooth_pixels
from web_shot import EXAMPLES, MODEL_VIEWER_EXPOSURE_GAIN, missing_browser, shoot

RESOLUTION = 256


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
    shown = assert_shows(look, expected, chosen)
    print(f"{viewer} shows {name}: {shown}")
    assert nothing_outside(look, covered)
