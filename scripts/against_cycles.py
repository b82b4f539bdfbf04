"""Measures a bake against Cycles' own, texel for texel, on Suzanne as a 20 cm head in Blender's
skin (Principled, Random Walk, Base Color (0.8, 0.55, 0.45), Radius (1, 0.35, 0.2), IOR 1.4)
under a sun and a point light, at the Subsurface Scale of the bundled examples (0.002) and at
Blender's default (0.05, the reach of real skin). For each method asked, it prints per channel
the median of ours/Cycles and the 90th percentile of |ln(ours/Cycles)| over lit texels (at
least a tenth of the channel's brightest) after a 3×3 box on both maps (Cycles' noise), and
the share of our light on texels where Cycles has under a hundredth of its brightest.

    PATH=$PWD/.venv/bin:$PATH .venv/bin/python -m pip install --no-build-isolation .
    .venv/bin/python scripts/against_cycles.py [--resolution 256] [--samples 256] [METHOD ...]

METHOD is a method of the add-on (AUTO, BRUTE, WALK, ...; AUTO when none). `--ior`,
`--roughness`, `--sun-only`, `--scale` and `--bounces` change the scene or the bake to tell
causes apart. With `--keep DIR` Cycles' bake is kept in DIR and read from there for the same
scene and samples, so a change to sssbake is measured again without Cycles baking again; our
maps are saved beside it (NumPy arrays, RGBA by texel)."""

import argparse
import pathlib
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCALES = (0.002, 0.05)


def head_scene(bpy, scale, ior=1.4, roughness=0.5, point_light=True):
    """Suzanne (subdivided twice, 20 cm) in skin at Subsurface Scale `scale` (IOR `ior`,
    Roughness `roughness`), a sun and (with `point_light`) a point light, a black world; the
    head selected, its UVs made by Smart UV Project."""
    from skin_material import principled_skin  # tests/, on the path main() sets

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_monkey_add(size=0.2)
    head = bpy.context.active_object
    head.name = "Head"
    head.modifiers.new("smooth", "SUBSURF").levels = 2
    bpy.ops.object.modifier_apply(modifier="smooth")
    bpy.ops.object.shade_smooth()
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.uv.smart_project(island_margin=0.01)
    bpy.ops.object.mode_set(mode="OBJECT")
    material = principled_skin(scale, ior, roughness, "RANDOM_WALK")
    head.data.materials.append(material)
    bpy.ops.object.light_add(type="SUN", rotation=(1.1, 0.0, 0.9))
    bpy.context.active_object.data.energy = 1.2
    bpy.context.active_object.data.angle = 0.0
    if point_light:
        bpy.ops.object.light_add(type="POINT", location=(-0.25, -0.3, 0.1))
        bpy.context.active_object.data.energy = 6.0
        bpy.context.active_object.data.shadow_soft_size = 0.0
    bpy.context.scene.world = None
    bpy.ops.object.select_all(action="DESELECT")
    head.select_set(True)
    bpy.context.view_layer.objects.active = head
    return material


def box(image, covered):
    """A 3×3 box over the `covered` texels of `image`."""
    mask = covered.astype(np.float64)
    total = np.zeros(image.shape[:2] + (3,))
    weight = np.zeros(image.shape[:2])
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            total += np.roll(image[..., :3] * mask[..., None], (dy, dx), axis=(0, 1))
            weight += np.roll(mask, (dy, dx), axis=(0, 1))
    return total / np.maximum(weight, 1)[..., None]


def compare(ours, cycles):
    """The table's row: channel by channel over the texels both maps cover (alpha > 0) whose
    3×3 neighbours they cover too (Cycles bakes a texel only where its centre lies on a
    triangle; sssbake also bakes the texels a chart's edge crosses)."""
    both = (ours[..., 3] > 0) & (cycles[..., 3] > 0)
    ours_box, cycles_box = box(ours, both), box(cycles, both)
    neighbours = sum(np.roll(both, (dy, dx), axis=(0, 1)) for dy in (-1, 0, 1) for dx in (-1, 0, 1))
    covered = both & (neighbours == 9)
    rows = []
    for c, name in enumerate("RGB"):
        top = cycles_box[..., c][covered].max()
        lit = covered & (cycles_box[..., c] > 0.1 * top)
        ratio = ours_box[..., c][lit] / cycles_box[..., c][lit]
        dark = covered & (cycles_box[..., c] < 0.01 * top)
        stray = ours_box[..., c][dark].sum() / max(ours_box[..., c][covered].sum(), 1e-30)
        rows.append(
            f"{name}: median {np.median(ratio):.3f}, p90 |ln| {np.percentile(np.abs(np.log(ratio)), 90):.3f}, "
            f"light where Cycles has none {100 * stray:.1f}%"
        )
    return "; ".join(rows)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("methods", nargs="*", default=["AUTO"])
    parser.add_argument("--resolution", type=int, default=256)
    parser.add_argument("--samples", type=int, default=256)
    parser.add_argument("--scale", type=float, action="append", help="Subsurface Scale (repeatable)")
    parser.add_argument("--ior", type=float, default=1.4)
    parser.add_argument("--roughness", type=float, default=0.5)
    parser.add_argument("--sun-only", action="store_true", help="leave the point light out")
    parser.add_argument(
        "--bounces", type=int, help="bounces of the head's light onto itself (the add-on's own)"
    )
    parser.add_argument(
        "--keep",
        type=pathlib.Path,
        help="a folder to keep Cycles' bake in (read from there for the same scene and samples) and ours beside it",
    )
    args = parser.parse_args()
    sys.path.insert(0, str(ROOT / "tests"))
    import bpy
    from conftest import load_extension
    from test_cycles_parity import baked_exitance, cycles_exitance

    for scale in args.scale or SCALES:
        material = head_scene(bpy, scale, args.ior, args.roughness, not args.sun_only)
        start = time.monotonic()
        settings = (
            f"{scale}_{args.resolution}_{args.samples}_{args.ior}_{args.roughness}_{int(args.sun_only)}"
        )
        kept = args.keep and args.keep / f"cycles_{settings}.npy"
        if kept and kept.exists():
            cycles = np.load(kept)
        else:
            cycles = cycles_exitance(material, args.resolution, args.samples)
            if kept:
                args.keep.mkdir(parents=True, exist_ok=True)
                np.save(kept, cycles)
        print(
            f"Subsurface Scale {scale}: Cycles at {args.samples} samples in {time.monotonic() - start:.0f} s",
            flush=True,
        )
        module = load_extension("sssbake", ROOT / "blender_addon")
        module.register()
        for method in args.methods:
            bpy.context.scene.sssbake.method = method
            if args.bounces is not None:
                bpy.context.scene.sssbake.bounces = args.bounces
            result = bpy.ops.sssbake.bake(resolution=args.resolution, uv_map="UVMap", outputs={"DIFFUSE"})
            if result != {"FINISHED"}:
                sys.exit("the bake failed; its report is above")
            ours = baked_exitance("Head")
            if args.keep:
                np.save(args.keep / f"ours_{method}_{scale}_{args.resolution}.npy", ours)
            print(f"  {method}: {compare(ours, cycles)}", flush=True)
        module.unregister()


if __name__ == "__main__":
    main()
