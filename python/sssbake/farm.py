"""An sssbake batch on a Dask distributed cluster: one task per asset of
the manifest, each running the `sssbake` binary's single-asset path

    sssbake batch MANIFEST --out OUT --asset NAME

on a worker, which bakes the asset into a hidden folder in OUT and moves it
into place whole (so a task retried after its worker died never leaves a
mixed folder), then writes `OUT/reports/NAME.json`. When every task has
ended, `sssbake batch MANIFEST --out OUT --collect` writes the batch's
report, `OUT/batch.json`, which `run` returns.

Workers need the `sssbake` binary and the manifest, its assets and OUT at
the same paths as the client (shared storage); they do not need this
module, which is sent to them by value.

    from distributed import Client
    from sssbake import farm
    report = farm.run("assets/batch.toml", "/shared/baked", Client("tcp://scheduler:8786"))
    assert report["counts"]["failed"] == 0

or from a shell, printing the batch report (exit 0, or 5 when some asset
failed):

    python python/sssbake/farm.py assets/batch.toml --out /shared/baked \
        --scheduler tcp://scheduler:8786
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tomllib
import uuid
from pathlib import Path
from typing import Any

# Exit code of `sssbake batch` when an asset failed (README "Pipelines"):
# the task ran; its report says why the asset failed.
SOME_FAILED = 5


class FarmError(RuntimeError):
    """A task that could not run `sssbake` (not an asset that failed: that
    is in the report)."""


def asset_names(manifest: str | os.PathLike[str]) -> list[str]:
    """The asset names of `manifest`, in the order sssbake runs them."""
    with open(manifest, "rb") as file:
        return sorted(tomllib.load(file).get("assets", {}))


def bake_asset(sssbake: str, manifest: str, out: str, asset: str, threads: int | None) -> dict[str, Any]:
    """Runs `sssbake batch` for `asset` alone, with `threads` threads
    (default: every core of the worker); returns the asset's report."""
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    command = [sssbake, "batch", manifest, "--out", out, "--asset", asset, "--json"]
    result = subprocess.run(command, check=False, capture_output=True, text=True, env=env)
    if result.returncode not in (0, SOME_FAILED):
        last = (result.stderr.strip().splitlines() or ["no message"])[-1]
        raise FarmError(f"{asset}: sssbake exited with {result.returncode}: {last}")
    return json.loads(result.stdout)["assets"][0]


def run(
    manifest: str | os.PathLike[str],
    out: str | os.PathLike[str],
    client: Any,
    *,
    sssbake: str = "sssbake",
    threads_per_task: int | None = None,
    retries: int = 2,
) -> dict[str, Any]:
    """Bakes every asset of `manifest` into `out` on the cluster of
    `client` (a `distributed.Client`), one task per asset; returns the
    batch report (as `sssbake batch --json` prints it) and writes it to
    `out/batch.json`.

    A task whose worker is lost is run again elsewhere by the scheduler
    (up to its `allowed-failures`); a task that raises is retried
    `retries` times. `threads_per_task` caps each bake's threads: give a
    worker's cores divided by its task slots, so tasks do not
    oversubscribe the cores."""
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    manifest = str(Path(manifest).resolve())
    out = str(Path(out).resolve())
    names = asset_names(manifest)

    def task(asset: str) -> dict[str, Any]:
        # A local function: pickle cannot send it by reference, so Dask sends
        # it (and this module) by value, and workers need only the binary.
        return bake_asset(sssbake, manifest, out, asset, threads_per_task)

    futures = client.map(
        task,
        names,
        key=[f"sssbake-{name}-{uuid.uuid4().hex}" for name in names],
        retries=retries,
        pure=False,
    )
    client.gather(futures)
    result = subprocess.run(
        [sssbake, "batch", manifest, "--out", out, "--collect", "--json"],
        check=False,
        capture_output=True,
        text=True,
    )
    if result.returncode not in (0, SOME_FAILED):
        last = (result.stderr.strip().splitlines() or ["no message"])[-1]
        raise FarmError(f"collecting the reports failed: {last}")
    return json.loads(result.stdout)


def main(argv: list[str] | None = None) -> int:
    """`farm.py MANIFEST --out DIR --scheduler ADDRESS`: runs the batch on the
    cluster at ADDRESS and prints its report; the exit code is sssbake's."""
    from distributed import Client

    parser = argparse.ArgumentParser(description="Run an sssbake batch on a Dask cluster.")
    parser.add_argument("manifest")
    parser.add_argument("--out", required=True, help="the batch's folder, on storage every worker shares")
    parser.add_argument("--scheduler", required=True, help="the Dask scheduler, such as tcp://host:8786")
    parser.add_argument("--sssbake", default="sssbake", help="the sssbake binary on the workers")
    parser.add_argument("--threads-per-task", type=int, help="threads of each bake [every core]")
    args = parser.parse_args(argv)
    with Client(args.scheduler) as client:
        report = run(
            args.manifest, args.out, client, sssbake=args.sssbake, threads_per_task=args.threads_per_task
        )
    print(json.dumps(report, indent=2))
    counts = report["counts"]
    return 0 if counts["failed"] == 0 and counts["missing"] == 0 else SOME_FAILED


if __name__ == "__main__":
    sys.exit(main())
