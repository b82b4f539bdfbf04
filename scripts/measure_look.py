"""Measures how the glTF copy of a bake encodes the look, against the sRGB preview.

Run as `.venv/bin/python scripts/measure_look.py DIR`, DIR the folder `sssbake bake` wrote for
a glTF input. For every baked material of the copy it prints the emissive strength S, the
covered texels (any channel above zero in the `diffuse` EXR), how many of them the sRGB
preview `<object>_diffuse.png` holds at 255 in some channel (clipped where the map is above 1)
and how many the emissive PNG does, and how far the emissive PNG, decoded from sRGB and
multiplied by S, is from the EXR on the texels above 5% of S.
"""

import json
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "tests"))
from conftest import exr, png_rgb, srgb_to_linear


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: measure_look.py DIR")
    out = pathlib.Path(sys.argv[1])
    copies = sorted(out.glob("*.gltf"))
    if not copies:
        sys.exit(f"{out}: no .gltf copy")
    copy = json.loads(copies[0].read_text())
    for material in copy.get("materials", []):
        strength = (
            material.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength")
        )
        if strength is None or "emissiveTexture" not in material:
            continue
        texture = copy["textures"][material["emissiveTexture"]["index"]]
        emissive_name = copy["images"][texture["source"]]["uri"]
        stem = emissive_name.removesuffix("_emissive.png")
        diffuse = exr(out / f"{stem}.exr").astype(np.float64)
        covered = (diffuse > 0).any(axis=2)
        preview = png_rgb(out / f"{stem}.png")
        emissive = png_rgb(out / emissive_name)
        clipped_preview = ((preview == 255).any(axis=2) & covered).sum()
        at_255 = ((emissive == 255).any(axis=2) & covered).sum()
        decoded = srgb_to_linear(emissive / 255) * strength
        bright = diffuse > 0.05 * strength
        relative = np.abs(decoded[bright] - diffuse[bright]) / diffuse[bright]
        n = covered.sum()
        print(f"{material['name']}: S = {strength:.4g} (EXR maximum {diffuse.max():.4g})")
        print(f"  covered texels: {n}")
        print(
            f"  sRGB preview {stem}.png at 255 in some channel: {clipped_preview} ({100 * clipped_preview / n:.1f}%)"
        )
        print(f"  emissive {emissive_name} at 255 in some channel: {at_255} ({100 * at_255 / n:.3f}%)")
        print(
            f"  emissive × S against the EXR above 5% of S: median {100 * np.median(relative):.2f}%, "
            f"maximum {100 * relative.max():.2f}% ({bright.sum()} texel channels)"
        )


main()
