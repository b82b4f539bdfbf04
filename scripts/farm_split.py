"""Measures what splitting a large asset into object tasks buys on the Dask
farm: a LocalCluster of two single-threaded worker processes bakes the ear
with a second shell behind it (two objects, tests/test_batch_objects.py) at
the given resolution, once as one task and once as an object task per
object and an assembly; prints both wall times and the plan's work
estimate, and checks the two folders are byte-identical.

    .venv/bin/python scripts/farm_split.py --resolution 512
"""

import argparse
import json
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from distributed import Client, LocalCluster
from test_batch_farm import farm, maps
from test_batch_objects import pair_assets

MANIFEST = """
[defaults]
resolution = {resolution}

[assets.pair]
scene = "ear/pair.gltf"
preset = "skin1"
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", type=int, default=512)
    parser.add_argument("--sssbake", default=str(ROOT / "target" / "release" / "sssbake"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        manifest = pair_assets(tmp, MANIFEST.format(resolution=args.resolution))
        tasks = subprocess.run(
            [args.sssbake, "batch", str(manifest), "--tasks"], check=True, capture_output=True, text=True
        )
        print(f"the plan's work estimate: {json.loads(tasks.stdout)[0]['work']:.3g}")
        with (
            LocalCluster(
                n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
            ) as cluster,
            Client(cluster) as client,
        ):
            for name, split_above in [("one task", float("inf")), ("object tasks", 0.0)]:
                start = time.perf_counter()
                report = farm.run(
                    manifest,
                    tmp / name,
                    client,
                    sssbake=args.sssbake,
                    threads_per_task=1,
                    split_above=split_above,
                )
                assert report["counts"]["baked"] == 1, report
                objects = report["assets"][0]["summary"]["objects"]
                stages = ", ".join(f"{o['name']} {sum(o['seconds'].values()):.1f} s" for o in objects)
                print(f"{name}: {time.perf_counter() - start:.1f} s (the objects' bakes: {stages})")
        assert maps(tmp / "one task") == maps(tmp / "object tasks"), "the folders differ"
        print("the two folders are byte-identical")


if __name__ == "__main__":
    main()
