"""A baked example's glTF copy shown by a web viewer (three.js or model-viewer) in headless
Chromium, screenshotted, with each pixel's texture coordinates from a second pass of the
same view (tests/viewer/shoot.mjs). The web viewers' test and scripts/viewer_pictures.py
both look through it."""

import json
import math
import os
import pathlib
import shutil
import subprocess

import numpy as np
from conftest import ROOT, png_rgb, srgb_to_linear

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
    """Why the browser cannot be driven here, or None."""
    if shutil.which("node") is None:
        return "Node.js is not installed"
    if not CHROMIUM.exists():
        return f"Chromium is not at {CHROMIUM} (Debian: apt-get install chromium; or set CHROMIUM)"
    for package in ("three", "@google/model-viewer", "playwright-core"):
        if not (NODE_MODULES / package).exists():
            return f"the npm package {package} is not in .node (run scripts/install-test-deps.sh)"
    return None


def camera(copy_path: pathlib.Path, name: str) -> dict:
    """The example's camera in the copy's (glTF, Y up) frame: orbit (θ, φ, radius in
    metres) around the centre of the mesh's bounds, framing them in FIELD_OF_VIEW."""
    _, _, theta, phi = EXAMPLES[name]
    copy = json.loads(copy_path.read_text())
    low, high = np.array(copy["accessors"][0]["min"]), np.array(copy["accessors"][0]["max"])
    half_diagonal = float(np.linalg.norm(high - low)) / 2
    radius = 0.9 * half_diagonal / math.sin(math.radians(FIELD_OF_VIEW / 2))
    return {
        "orbit": {"theta": theta, "phi": phi, "radius": radius},
        "target": ((low + high) / 2).tolist(),
        "fov": FIELD_OF_VIEW,
    }


def shoot(viewer: str, out: pathlib.Path, name: str, exposure: float, work: pathlib.Path) -> dict:
    """Shows `out`/<name>.gltf in `viewer` with a linear exposure (three.js: linear tone
    mapping; model-viewer: its defaults and this exposure). Returns the screenshot (linear
    display values, rows top to bottom), its PNG, the texture coordinates and coverage of
    the uv pass, and the page's report."""
    copy_path = out / f"{name}.gltf"
    copy = json.loads(copy_path.read_text())
    (material,) = [m for m in copy["materials"] if m["name"].endswith("(sssbake)")]
    texcoord = material["emissiveTexture"].get("texCoord", 0)
    view = {
        "viewer": viewer,
        "asset": str(copy_path),
        "size": SIZE,
        **camera(copy_path, name),
        "toneMapping": "linear",
        "exposure": exposure,
        "uvAttribute": "uv" if texcoord == 0 else f"uv{texcoord}",
    }
    view_file = work / f"{viewer}-{name}.json"
    view_file.write_text(json.dumps(view))
    prefix = work / f"{viewer}-{name}"
    result = subprocess.run(
        ["node", str(SHOOT), str(view_file), str(prefix)],
        capture_output=True,
        text=True,
        check=False,
        timeout=300,
    )
    if result.returncode != 0:
        raise RuntimeError(f"{viewer} could not show {copy_path}: {result.stderr}")
    screenshot = pathlib.Path(f"{prefix}_look.png")
    look = srgb_to_linear(png_rgb(screenshot) / 255)
    uv = np.fromfile(f"{prefix}_uv.f32", dtype=np.float32).reshape(SIZE, SIZE, 4)[::-1].astype(np.float64)
    report = json.loads(pathlib.Path(f"{prefix}.json").read_text())
    return {"look": look, "png": screenshot, "uv": uv[..., :2], "covered": uv[..., 3] > 0.5, "report": report}
