"""Times the exact sum (`--method brute`) and the default bake of two sssbake
binaries side by side on the bundled assets, and prints their ratio.

The machine may be shared, so each case runs the two binaries one after the
other, `--repeats` times, on one thread, and keeps the least scattering time
each took (the summary's `seconds.scattering`: CPU spent integrating and
checking, without layout, lighting and writing).

    cargo build --release -p sssbake-cli
    git worktree add /tmp/before <commit> && (cd /tmp/before && cargo build --release -p sssbake-cli)
    .venv/bin/python scripts/bench_exact_sum.py /tmp/before/target/release/sssbake target/release/sssbake
"""

import argparse
import json
import subprocess
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# (label, asset, resolution, extra arguments)
CASES = [
    ("head, own skin, brute", "head", 256, ["--method", "brute"]),
    ("head, own skin, brute", "head", 512, ["--method", "brute"]),
    ("ear, own skin, brute", "ear", 256, ["--method", "brute"]),
    ("marble, own, brute", "marble", 256, ["--method", "brute"]),
    ("head, skin1, brute", "head", 256, ["--method", "brute", "--preset", "skin1"]),
    ("head, own skin, default", "head", 1024, []),
]


def scattering_seconds(binary: str, asset: str, resolution: int, extra: list[str]) -> float:
    """The scattering seconds of one bake into a fresh folder."""
    with tempfile.TemporaryDirectory() as out:
        command = [
            binary,
            "bake",
            str(ROOT / "examples" / asset / f"{asset}.gltf"),
            "--out",
            out,
            "--resolution",
            str(resolution),
            "--threads",
            "1",
            "--json",
            *extra,
        ]
        result = subprocess.run(command, check=True, capture_output=True, text=True)
    summary = json.loads(result.stdout)
    return sum(o["seconds"]["scattering"] for o in summary["objects"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", help="the binary to compare against")
    parser.add_argument("after", help="the binary measured")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print("| case | resolution | before s | after s | before/after |")
    print("|---|---|---|---|---|")
    for label, asset, resolution, extra in CASES:
        before, after = [], []
        for _ in range(args.repeats):
            before.append(scattering_seconds(args.before, asset, resolution, extra))
            after.append(scattering_seconds(args.after, asset, resolution, extra))
        b, a = min(before), min(after)
        print(f"| {label} | {resolution}² | {b:.2f} | {a:.2f} | {b / a:.1f}× |", flush=True)


if __name__ == "__main__":
    main()
