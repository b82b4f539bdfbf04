"""Measures the Dask farm's throughput on the bundled examples: a LocalCluster
of two single-threaded worker processes bakes the head, marble and ear (glTF)
and the head (USD) at the given resolution into a fresh folder; prints the
wall time and the assets per hour, per worker and for the cluster, and the
same batch run locally with `sssbake batch --jobs 2` for comparison.

    .venv/bin/python scripts/farm_throughput.py --resolution 512
"""

import argparse
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from distributed import Client, LocalCluster
from test_batch import MANIFEST
from test_batch_farm import farm


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", type=int, default=512)
    parser.add_argument("--sssbake", default=str(ROOT / "target" / "release" / "sssbake"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = pathlib.Path(tmp) / "assets"
        shutil.copytree(ROOT / "examples", folder, ignore=shutil.ignore_patterns("*.py"))
        manifest = folder / "batch.toml"
        manifest.write_text(MANIFEST.replace("resolution = 64", f"resolution = {args.resolution}"))
        with (
            LocalCluster(
                n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
            ) as cluster,
            Client(cluster) as client,
        ):
            start = time.perf_counter()
            report = farm.run(
                manifest, pathlib.Path(tmp) / "farm", client, sssbake=args.sssbake, threads_per_task=1
            )
            seconds = time.perf_counter() - start
        assets = report["counts"]["baked"]
        print(f"farm: {assets} assets at {args.resolution}² in {seconds:.1f} s on 2 workers:")
        print(
            f"  {assets / seconds * 3600:.0f} assets/hour for the cluster, {assets / seconds * 3600 / 2:.0f} per worker"
        )
        for asset in report["assets"]:
            print(f"  {asset['name']}: {asset['seconds']:.1f} s")
        start = time.perf_counter()
        subprocess.run(
            [args.sssbake, "batch", str(manifest), "--out", str(pathlib.Path(tmp) / "local"), "--jobs", "2"],
            check=True,
            capture_output=True,
        )
        seconds = time.perf_counter() - start
        print(f"local, sssbake batch --jobs 2: {seconds:.1f} s, {assets / seconds * 3600:.0f} assets/hour")


if __name__ == "__main__":
    main()
