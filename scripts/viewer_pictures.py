"""The baked look beside the render it replaces. The bundled head's own Blender scene
(examples/make_examples.py) is rendered by Cycles with its subsurface scattering (Random
Walk), and the head's glTF copy, baked by sssbake, is drawn by three.js and by
model-viewer in headless Chromium from the same camera. Writes docs/viewing_cycles.png,
docs/viewing_three.png and docs/viewing_model_viewer.png, the ear's and the marble's copies in
three.js as docs/viewing_three_ear.png and docs/viewing_three_marble.png, and prints how far
the baked look is from Cycles over the lit pixels:

    cargo build --release -p sssbake-cli
    .venv/bin/python scripts/viewer_pictures.py            # --samples 256 --resolution 1024

The picture's exposure puts the map's brightest texel at display white, in every picture.
Cycles' pixels are its whole render: the subsurface light the bake replaces, and the
specular highlights and the light the head sends onto itself, which the bake leaves out."""

import argparse
import os
import pathlib
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "examples"))

from conftest import exr
from web_shot import EXAMPLES, SIZE, camera, missing_browser, shoot


def write_png(path: pathlib.Path, display: np.ndarray):
    """Linear display values in [0, 1] (rows top to bottom) as an 8-bit sRGB PNG."""
    encoded = np.where(display <= 0.0031308, display * 12.92, 1.055 * np.power(display, 1 / 2.4) - 0.055)
    codes = np.round(np.clip(encoded, 0, 1) * 255).astype(np.uint8)
    height, width, _ = codes.shape
    raw = b"".join(b"\x00" + codes[y].tobytes() for y in range(height))

    def chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    path.write_bytes(
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", header)
        + chunk(b"IDAT", zlib.compress(raw, 9))
        + chunk(b"IEND", b"")
    )


def render_cycles(view: dict, samples: int, work: pathlib.Path) -> dict:
    """The head's Blender scene from the web camera (glTF's Y up is Blender's Z up), by
    Cycles, as linear radiance (rows top to bottom) and the pixels the head covers."""
    import bpy
    import OpenEXR
    from make_examples import SCENES
    from mathutils import Vector

    SCENES["head"]()
    scene = bpy.context.scene
    theta, phi, radius = (view["orbit"][k] for k in ("theta", "phi", "radius"))
    offset = radius * np.array([np.sin(phi) * np.sin(theta), np.cos(phi), np.sin(phi) * np.cos(theta)])
    to_blender = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    target = Vector(to_blender @ np.array(view["target"]))
    cam = bpy.data.objects.new("View", bpy.data.cameras.new("View"))
    cam.data.angle = np.radians(view["fov"])
    cam.location = target + Vector(to_blender @ offset)
    cam.rotation_euler = (target - cam.location).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(cam)
    scene.camera = cam
    world = bpy.data.worlds.new("Black")
    world.color = (0, 0, 0)
    scene.world = world
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.render.film_transparent = True
    scene.render.resolution_x = scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_mode = "RGBA"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = str(work / "cycles.exr")
    start = time.monotonic()
    bpy.ops.render.render(write_still=True)
    print(f"Cycles, {samples} samples at {SIZE}²: {time.monotonic() - start:.0f} s", flush=True)
    pixels = OpenEXR.File(str(work / "cycles.exr")).parts[0].channels["RGBA"].pixels.astype(np.float64)
    return {"radiance": pixels[..., :3], "covered": pixels[..., 3] > 0.999}


def box(image: np.ndarray) -> np.ndarray:
    """A 3 × 3 mean, for Cycles' noise."""
    padded = np.pad(image, ((1, 1), (1, 1), (0, 0)), mode="edge")
    rows, columns = image.shape[:2]
    return sum(padded[y : y + rows, x : x + columns] for y in range(3) for x in range(3)) / 9


def compare(ours: np.ndarray, cycles: np.ndarray, chosen: np.ndarray) -> str:
    ratio = box(ours)[chosen] / np.maximum(box(cycles)[chosen], 1e-9)
    median = np.median(ratio, axis=0)
    p90 = np.percentile(np.abs(np.log(np.maximum(ratio, 1e-9))), 90, axis=0)
    return (
        f"median ours/Cycles R/G/B {median[0]:.2f} / {median[1]:.2f} / {median[2]:.2f}, "
        f"p90 of |ln ratio| {p90[0]:.2f} / {p90[1]:.2f} / {p90[2]:.2f} over {chosen.sum()} pixels"
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=256, help="Cycles' samples per pixel")
    parser.add_argument("--resolution", type=int, default=1024, help="the bake's texels per side")
    args = parser.parse_args()
    reason = missing_browser()
    if reason is not None:
        sys.exit(f"cannot drive the web viewers: {reason}")
    binary = pathlib.Path(os.environ.get("SSSBAKE_BIN", ROOT / "target" / "release" / "sssbake"))
    with tempfile.TemporaryDirectory() as folder:
        work = pathlib.Path(folder)
        out = work / "bake"
        subprocess.run(
            [str(binary), "bake", str(ROOT / "examples" / "head" / "head.gltf"), "--out", str(out)]
            + ["--resolution", str(args.resolution), "--light-check", "0"],
            check=True,
        )
        exposure = 1.0 / float(exr(out / "Head_diffuse.exr").max())
        three = shoot("three", out, "head", exposure, work)
        viewer = shoot("model-viewer", out, "head", exposure, work)
        shutil.copy(three["png"], ROOT / "docs" / "viewing_three.png")
        shutil.copy(viewer["png"], ROOT / "docs" / "viewing_model_viewer.png")
        for name in ("ear", "marble"):
            scene, object_name, *_ = EXAMPLES[name]
            folder = work / name
            subprocess.run(
                [str(binary), "bake", str(ROOT / scene), "--out", str(folder)]
                + ["--resolution", str(args.resolution), "--light-check", "0"],
                check=True,
            )
            shown = 1.0 / float(exr(folder / f"{object_name}_diffuse.exr").max())
            shot = shoot("three", folder, name, shown, work)
            shutil.copy(shot["png"], ROOT / "docs" / f"viewing_three_{name}.png")
        cycles = render_cycles(camera(out / "head.gltf", "head"), args.samples, work)
        write_png(ROOT / "docs" / "viewing_cycles.png", np.clip(exposure * cycles["radiance"], 0, 1))

    # three.js shows the radiance times the exposure, clipped at 1: compare below the clip,
    # over pixels both cover (away from the silhouette) and lit above 1% of white.
    ours = three["look"] / exposure
    lit = (three["look"] > 0.01).all(axis=2) & (three["look"] < 0.99).all(axis=2)
    both = three["covered"] & cycles["covered"]
    inside = box(both[..., None].astype(float))[..., 0] > 0.999
    chosen = inside & lit
    print("baked look in three.js against Cycles: " + compare(ours, cycles["radiance"], chosen))
    print("wrote docs/viewing_cycles.png, docs/viewing_three.png, docs/viewing_model_viewer.png,")
    print("      docs/viewing_three_ear.png, docs/viewing_three_marble.png")


if __name__ == "__main__":
    main()
