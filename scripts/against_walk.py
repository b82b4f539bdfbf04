"""The default bake against light itself at every texel: a bundled asset baked by the default
method and by the volumetric random walk through its mesh (`--method walk`), both through the
release binary with margin 0, compared texel for texel. Per channel it prints the relative
RMSE over covered texels, the median of bake/walk and the 90th percentile of |ln(bake/walk)|
over texels with at least a tenth of the walk's brightest, and the ratio of their sums in bins
of the walk's own light (as a share of its brightest): where the bake puts too much or too
little light, lit skin or skin in shadow. A second table splits the lit texels by the
thickness the bake finds behind them (`thickness` map, thinner than 20 mm or not): how many
are thin, what share of the texels past the 90th percentile they are, and each part's median.

    cargo build --release -p sssbake-cli
    .venv/bin/python scripts/against_walk.py [--scene examples/head/head.gltf] [--resolution 128]
        [--walks 2048] [--preset skin1] [--keep-walk DIR]

With `--keep-walk DIR` the walk's bake is kept in DIR and read from there when it is already
there (for the same scene, resolution, walks and preset), so a change to the bake is measured
again without walking again. The walk's own noise (its relative standard error per channel) is printed with it; at 128² and
2048 walks per texel the head takes about 6 minutes on two cores.
"""

import argparse
import itertools
import json
import pathlib
import tempfile

import numpy
from bench_assets import bake, rgb

BINS = (0.0, 0.01, 0.03, 0.1, 0.2, 0.4, 0.7, 1.0001)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default="examples/head/head.gltf")
    parser.add_argument("--resolution", type=int, default=128)
    parser.add_argument("--walks", type=int, default=2048, help="walks per texel and channel")
    parser.add_argument("--preset", help="a material preset instead of the asset's own")
    parser.add_argument(
        "--keep-walk", type=pathlib.Path, help="a folder to keep the walk's bake in and read it from"
    )
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        folder = pathlib.Path(folder)
        maps = {}
        for method in ("auto", "walk"):
            out = folder / method
            if method == "walk" and args.keep_walk:
                out = args.keep_walk / "_".join(
                    [
                        pathlib.Path(args.scene).stem,
                        str(args.resolution),
                        str(args.walks),
                        args.preset or "own",
                    ]
                )
                kept = out / "summary.json"
                if kept.exists():
                    summary = json.loads(kept.read_text())
                    stem = summary["objects"][0]["file_stem"]
                    maps[method] = rgb(out / f"{stem}_subsurface.exr")
                    print(f"walk: read from {out}")
                    continue
            extra = ["--light-check", "0", "--walk-samples", str(args.walks)]
            outputs = "subsurface,area,thickness" if method == "auto" else "subsurface"
            seconds, summary = bake(args.scene, out, args.resolution, method, args.preset, outputs, extra)
            if method == "walk" and args.keep_walk:
                (out / "summary.json").write_text(json.dumps(summary))
            walk = summary["objects"][0]["accuracy"].get("walk")
            noise = ""
            if walk:
                error = " / ".join(f"{100 * e:.1f}%" for e in walk["relative_standard_error"])
                noise = f", {walk['samples']} walks per texel, relative standard error {error} (R/G/B)"
            print(f"{method}: {seconds:.1f} s{noise}")
            stem = summary["objects"][0]["file_stem"]
            maps[method] = rgb(out / f"{stem}_subsurface.exr")
            if method == "auto":
                area = rgb(out / f"{stem}_area.exr")
                thickness = rgb(out / f"{stem}_thickness.exr")[..., 0]
    baked, walked = maps["auto"], maps["walk"]
    covered = area[..., 0] > 0
    print("| channel | rel. RMSE | median | p90 abs(ln) | " + " | ".join(bin_names()) + " |")
    print("|---" * (4 + len(BINS) - 1) + "|")
    for c, name in enumerate("RGB"):
        b, w = baked[..., c][covered], walked[..., c][covered]
        rmse = numpy.sqrt(((b - w) ** 2).mean() / (w**2).mean())
        lit = w > 0.1 * w.max()
        ratio = b[lit] / w[lit]
        share = w / w.max()
        sums = []
        for low, high in itertools.pairwise(BINS):
            inside = (share >= low) & (share < high)
            sums.append(f"{b[inside].sum() / max(w[inside].sum(), 1e-30):.2f}" if inside.any() else "-")
        print(
            f"| {name} | {100 * rmse:.1f}% | {numpy.median(ratio):.3f} | "
            f"{numpy.percentile(numpy.abs(numpy.log(ratio)), 90):.3f} | " + " | ".join(sums) + " |"
        )
    by_thickness(baked, walked, covered, thickness)


def by_thickness(baked, walked, covered, thickness, thin_mm=20.0):
    """Lit texels thinner than `thin_mm` against the rest, per channel."""
    print(
        f"| channel | lit texels thinner than {thin_mm:g} mm | their share past p90 | median thin | median thick |"
    )
    print("|---|---|---|---|---|")
    for c, name in enumerate("RGB"):
        b, w, t = baked[..., c][covered], walked[..., c][covered], thickness[covered]
        lit = w > 0.1 * w.max()
        log_ratio = numpy.log(b[lit] / w[lit])
        thin = t[lit] < thin_mm
        past = numpy.abs(log_ratio) > numpy.percentile(numpy.abs(log_ratio), 90)
        median = [
            f"{numpy.exp(numpy.median(log_ratio[part])):.3f}" if part.any() else "-" for part in (thin, ~thin)
        ]
        print(f"| {name} | {thin.mean():.0%} | {thin[past].mean():.0%} | {median[0]} | {median[1]} |")


def bin_names():
    return [f"{low:g}–{min(high, 1):g}" for low, high in itertools.pairwise(BINS)]


if __name__ == "__main__":
    main()
