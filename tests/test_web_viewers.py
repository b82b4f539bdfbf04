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


def bilinear(image: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """`image` (rows top to bottom) at glTF texture coordinates (origin at the top left),
    filtered bilinearly between texel centres, as a GPU samples it."""
    height, width, _ = image.shape
    x = np.clip(u * width - 0.5, 0, width - 1)
    y = np.clip(v * height - 0.5, 0, height - 1)
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    x1, y1 = np.minimum(x0 + 1, width - 1), np.minimum(y0 + 1, height - 1)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    top = image[y0, x0] * (1 - fx) + image[y0, x1] * fx
    bottom = image[y1, x0] * (1 - fx) + image[y1, x1] * fx
    return top * (1 - fy) + bottom * fy


def window_spread(image: np.ndarray, size: int) -> tuple[np.ndarray, np.ndarray]:
    """Per pixel and channel, the largest and smallest value in the size × size window
    whose top left is `size // 2` pixels up and left (edges repeated)."""
    before = size // 2
    padded = np.pad(image, ((before, size - 1 - before), (before, size - 1 - before), (0, 0)), mode="edge")
    rows, columns = image.shape[:2]
    windows = np.stack([padded[y : y + rows, x : x + columns] for y in range(size) for x in range(size)])
    return windows.max(axis=0), windows.min(axis=0)


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
    radiance = np.zeros_like(look)
    radiance[covered] = bilinear(diffuse, uv[covered, 0], uv[covered, 1])
    if viewer == "three":
        expected = np.clip(exposure * radiance, 0, 1)
    else:
        assert report["toneMapping"] == "auto" and report["environment"] is None
        expected = pbr_neutral(exposure * MODEL_VIEWER_EXPOSURE_GAIN * radiance)

    # Where the map is smooth: the pixel's 3 × 3 neighbours all on the object and within
    # 5% of each other, and the texels around the ones it filters within 5% too (not a
    # chart edge, where a coarser mip level mixes in the margin).
    inside = window_spread(covered[..., None].astype(float), 3)[1][..., 0] > 0.5
    high, low = window_spread(expected, 3)
    texel_high, texel_low = window_spread(diffuse, 4)
    height, width, _ = diffuse.shape
    tx = np.clip((uv[..., 0] * width - 0.5).astype(int), 0, width - 1)
    ty = np.clip((uv[..., 1] * height - 0.5).astype(int), 0, height - 1)
    # The 4 × 4 window at (tx + 1, ty + 1) holds the 2 × 2 texels filtered and one more on
    # each side.
    tx1, ty1 = np.minimum(tx + 1, width - 1), np.minimum(ty + 1, height - 1)
    texel_smooth = texel_high[ty1, tx1] <= 1.05 * texel_low[ty1, tx1]
    # A pixel spanning at most 2 texels, so the mip level it reads stays within that
    # window (not where a sphere's texture coordinates meet at its pole).
    texels = uv * np.array([width, height])
    step = np.maximum(
        np.abs(np.diff(texels, axis=0, append=texels[-1:])).max(axis=2),
        np.abs(np.diff(texels, axis=1, append=texels[:, -1:])).max(axis=2),
    )
    fine = step <= 2.0
    # Bright enough that one 8-bit step of the sRGB output is under 2%.
    chosen = (inside & fine)[..., None] & (high <= 1.05 * low) & texel_smooth & (expected > 0.2)
    assert chosen.sum() > 2000, chosen.sum()
    relative = np.abs(look[chosen] - expected[chosen]) / expected[chosen]
    assert np.median(relative) < 0.006, np.median(relative)
    assert relative.max() < 0.02, relative.max()
    # On average neither brighter (a second lighting) nor darker (a clip or a lost strength).
    assert abs(np.mean(look[chosen] / expected[chosen]) - 1) < 0.003

    # Nothing drawn where the object is not (away from its antialiased silhouette).
    near_object = window_spread(covered[..., None].astype(float), 5)[0][..., 0] > 0.5
    assert look[~near_object].max() == 0
