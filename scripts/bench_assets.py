"""The default bake against the exact sum on the bundled assets, in one run.

For each asset and material it bakes the subsurface map twice through the release
binary, once with `--method auto` (the default) and once with `--method brute` (the exact
sum), both with margin 0 so the covered texels are exactly those with area, and prints
each one's wall time, their ratio, the method `auto` chose, its own error estimate and the
error measured against the exact sum: relative RMSE over covered texels and channels, and
the 99.9th percentile of |M - M_brute| over the 99th percentile of M_brute. `--scaling`
adds the default bake of the head from 256² up, with its time over N log N;
`--first-command` the README's first command timed against the same bake by the exact sum
(at skin's reach, hours on two cores); `--speed` the head in skin1 and in marble and the ear
from 1024² up, with peak memory, the ratio to the bake of the irradiance alone and, at 1024²,
the error measured against the exact sum (`--resolution 0` leaves the first table out).

    cargo build --release -p sssbake-cli
    .venv/bin/python scripts/bench_assets.py [--resolution 512] [--scaling 2048] [--speed 4096]
        [--first-command]
"""

import argparse
import json
import math
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy
import OpenEXR

ROOT = pathlib.Path(__file__).resolve().parent.parent
# The release binary, or another build to compare with (SSSBAKE_BINARY).
BINARY = pathlib.Path(os.environ.get("SSSBAKE_BINARY", ROOT / "target" / "release" / "sssbake"))
CASES = [
    ("examples/head/head.gltf", None),
    ("examples/ear/ear.gltf", None),
    ("examples/marble/marble.gltf", None),
    ("examples/head/head.gltf", "skin1"),
    ("examples/head/head.gltf", "marble"),
    ("examples/head/head.gltf", "skin3layer"),
]


def bake(scene, out, resolution, method, preset, outputs="subsurface,area", extra=()):
    """Bakes (with the `extra` arguments) and returns (wall seconds, summary)."""
    command = [str(BINARY), "bake", str(ROOT / scene), "--out", str(out), "--force", "--json"]
    command += ["--resolution", str(resolution), "--method", method, "--margin", "0", "--outputs", outputs]
    command += list(extra)
    if preset:
        command += ["--preset", preset]
    if method == "brute":  # the reference, run on purpose past the default bound
        command += ["--max-evaluations", "1e13"]
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        sys.exit(f"{' '.join(command)} failed:\n{done.stderr}")
    return seconds, json.loads(done.stdout)


def rgb(path):
    return numpy.asarray(OpenEXR.File(str(path)).parts[0].channels["RGB"].pixels, dtype=numpy.float64)


def errors(got, exact, covered):
    """Relative RMSE and p99.9 |got - exact| / p99 exact over covered texels."""
    g, e = got[covered], exact[covered]
    rmse = math.sqrt(((g - e) ** 2).mean()) / math.sqrt((e**2).mean())
    tail = numpy.percentile(numpy.abs(g - e), 99.9) / numpy.percentile(e, 99)
    return rmse, tail


def compare(resolution):
    print(f"default (auto) against the exact sum at {resolution}², margin 0, wall seconds of the whole bake")
    print(
        "| asset | material | texels | auto chose | estimate | rel. RMSE | p99.9 | auto s | brute s | brute/auto |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for scene, preset in CASES:
        with tempfile.TemporaryDirectory() as folder:
            folder = pathlib.Path(folder)
            auto_s, summary = bake(scene, folder / "auto", resolution, "auto", preset)
            brute_s, _ = bake(scene, folder / "brute", resolution, "brute", preset)
            for obj in summary["objects"]:
                stem = obj["file_stem"]
                covered = rgb(folder / "brute" / f"{stem}_area.exr")[..., 0] > 0
                exact = rgb(folder / "brute" / f"{stem}_subsurface.exr")
                got = rgb(folder / "auto" / f"{stem}_subsurface.exr")
                rmse, tail = errors(got, exact, covered)
                accuracy = obj["accuracy"]
                print(
                    f"| {pathlib.Path(scene).stem} | {preset or 'own'} | {obj['texels']} | {accuracy['method']} "
                    f"| {100 * accuracy['estimated_error']:.2f}% | {100 * rmse:.2f}% | {100 * tail:.2f}% "
                    f"| {auto_s:.1f} | {brute_s:.1f} | {brute_s / auto_s:.1f}× |"
                )


def scaling(largest):
    print(f"\nthe default bake of the head (read → maps written), 256² to {largest}²")
    print("| resolution | texels | method | seconds | seconds / (N log₂ N) relative to 256² |")
    print("|---|---|---|---|---|")
    base = None
    resolution = 256
    while resolution <= largest:
        with tempfile.TemporaryDirectory() as folder:
            seconds, summary = bake("examples/head/head.gltf", folder, resolution, "auto", None, "subsurface")
        texels = summary["objects"][0]["texels"]
        cost = seconds / (texels * math.log2(texels))
        base = base or cost
        method = summary["objects"][0]["accuracy"]["method"]
        print(f"| {resolution}² | {texels} | {method} | {seconds:.1f} | {cost / base:.2f} |")
        resolution *= 2


# Kernel evaluations the exact sum may take in the speed table: a few minutes on two cores.
EXACT_BUDGET = 3e11

SPEED_CASES = [
    ("examples/head/head.gltf", "skin1"),
    ("examples/head/head.gltf", "marble"),
    ("examples/ear/ear.gltf", None),
]


def timed(command):
    """Runs `command`; returns (wall seconds, peak resident memory in bytes, stdout)."""
    start = time.perf_counter()
    child = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    out = child.stdout.read()
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"{' '.join(command)} failed")
    return seconds, usage.ru_maxrss * 1024, out


def speed(largest):
    """The default bake at skin's and marble's reach from 1024² up: seconds, peak memory, the
    estimate, the ratio to the bake of the irradiance alone (the lighting pass) and, at the
    smallest resolution, the error measured against the exact sum."""
    print(f"\nthe default bake (subsurface map) against the irradiance alone, 1024² to {largest}²")
    print(
        "| asset | material | resolution | method | estimate | rel. RMSE | p99.9 | seconds | peak memory "
        "| irradiance s | ratio |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for scene, preset in SPEED_CASES:
        resolution = 1024
        while resolution <= largest:
            with tempfile.TemporaryDirectory() as folder:
                runs = []
                for outputs in ("subsurface", "irradiance"):
                    command = [
                        str(BINARY),
                        "bake",
                        str(ROOT / scene),
                        "--out",
                        f"{folder}/{outputs}",
                        "--json",
                    ]
                    command += ["--resolution", str(resolution), "--margin", "0", "--outputs", outputs]
                    command += ["--preset", preset] if preset else []
                    runs.append(timed(command))
                (seconds, memory, out), (lit, _, _) = runs
                obj = json.loads(out)["objects"][0]
                measured = "| — | — "
                if resolution == 1024:  # the exact sum takes hours past it
                    measured = measured_error(scene, pathlib.Path(folder), preset, obj["file_stem"])
            accuracy = obj["accuracy"]
            print(
                f"| {pathlib.Path(scene).stem} | {preset or 'own'} | {resolution}² | {accuracy['method']} "
                f"| {100 * accuracy['estimated_error']:.2f}% {measured}| {seconds:.1f} "
                f"| {memory / 2**30:.2f} GiB | {lit:.1f} | {seconds / lit:.0f}× |"
            )
            resolution *= 2


def measured_error(scene, folder, preset, stem):
    """The table's cells of the error of `folder`/subsurface's map against the exact sum at
    1024², or why not: the exact sum is refused past EXACT_BUDGET kernel evaluations."""
    command = [str(BINARY), "bake", str(ROOT / scene), "--out", str(folder / "brute"), "--json"]
    command += ["--resolution", "1024", "--method", "brute", "--margin", "0", "--outputs", "subsurface,area"]
    command += ["--max-evaluations", str(EXACT_BUDGET)] + (["--preset", preset] if preset else [])
    if subprocess.run(command, capture_output=True, text=True, check=False).returncode != 0:
        return f"| exact sum over {EXACT_BUDGET:.0e} | — "
    covered = rgb(folder / "brute" / f"{stem}_area.exr")[..., 0] > 0
    exact = rgb(folder / "brute" / f"{stem}_subsurface.exr")
    got = rgb(folder / "subsurface" / f"{stem}_subsurface.exr")
    rmse, tail = errors(got, exact, covered)
    return f"| {100 * rmse:.2f}% | {100 * tail:.2f}% "


def first_command():
    """The README's first command (the head at the defaults: 1024², auto, every default output),
    and the same bake by the exact sum."""
    print("\nthe README's first command (read → maps written) against the same bake by the exact sum")
    print("| bake | method | estimate | seconds | brute/default |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        folder = pathlib.Path(folder)
        runs = []
        for extra in ([], ["--method", "brute", "--max-evaluations", "1e13"]):
            command = [str(BINARY), "bake", str(ROOT / "examples/head/head.gltf"), "--force", "--json"]
            command += ["--out", str(folder / ("brute" if extra else "default"))] + extra
            start = time.perf_counter()
            done = subprocess.run(command, capture_output=True, text=True, check=True)
            runs.append((time.perf_counter() - start, json.loads(done.stdout)["objects"][0]["accuracy"]))
    (default_s, default), (brute_s, _) = runs
    print(
        f"| default | {default['method']} | {100 * default['estimated_error']:.2f}% | {default_s:.1f} "
        f"| {brute_s / default_s:.1f}× |"
    )
    print(f"| brute | brute | 0.00% | {brute_s:.1f} | 1.0× |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", type=int, default=512)
    parser.add_argument("--scaling", type=int, default=0, help="largest resolution of the scaling table")
    parser.add_argument("--first-command", action="store_true", help="time the README's first command")
    parser.add_argument("--speed", type=int, default=0, help="largest resolution of the speed table")
    args = parser.parse_args()
    if not BINARY.exists():
        sys.exit(f"{BINARY} is missing: cargo build --release -p sssbake-cli")
    if args.resolution:
        compare(args.resolution)
    if args.speed:
        speed(args.speed)
    if args.scaling:
        scaling(args.scaling)
    if args.first_command:
        first_command()


if __name__ == "__main__":
    main()
