"""An sssbake batch on a Dask distributed cluster: one task per asset of
the manifest, each running the `sssbake` binary's single-asset path

    sssbake batch MANIFEST --out OUT --asset NAME

on a worker, which bakes the asset into a hidden folder in OUT and moves it
into place whole (so a task retried after its worker died never leaves a
mixed folder), then writes `OUT/reports/NAME.json`.

A large asset (several objects, planned above `split_above` rays, kernel
evaluations and probes; `sssbake batch MANIFEST --tasks` says which) is
one task per object instead,

    sssbake batch MANIFEST --out OUT --asset NAME --object OBJECT

each baking its object (seeing the whole scene) into a part in
`OUT/.parts/NAME/`, then one assembly task, depending on them,

    sssbake batch MANIFEST --out OUT --asset NAME --assemble

which builds the asset's folder from the parts exactly as the whole-asset
bake writes it. When every task has ended,
`sssbake batch MANIFEST --out OUT --collect` writes the batch's report,
`OUT/batch.json`, which `run` returns.

Workers need the `sssbake` binary and the manifest, its assets and OUT at
the same paths as the client (shared storage); they do not need this
module, which is sent to them by value.

    from distributed import Client
    from sssbake import farm
    report = farm.run("assets/batch.toml", "/shared/baked", Client("tcp://scheduler:8786"))
    assert report["counts"]["failed"] == 0

or from a shell, after `pip install "sssbake[farm]"`, printing the batch
report (exit 0, or 5 when some asset failed):

    sssbake-farm assets/batch.toml --out /shared/baked --scheduler tcp://scheduler:8786

(`python -m sssbake.farm …` is the same command).
"""

from __future__ import annotations

import argparse
import ctypes
import json
import os
import signal
import subprocess
import sys
import uuid
from collections.abc import Callable
from pathlib import Path
from typing import Any

# Exit code of `sssbake batch` when an asset failed (docs/pipelines.md):
# the task ran; its report says why the asset failed.
SOME_FAILED = 5


class FarmError(RuntimeError):
    """A task that could not run `sssbake` (not an asset that failed: that
    is in the report)."""


def sssbake_batch(
    sssbake: str, manifest: str, out: str, asset: str, extra: list[str], threads: int | None
) -> Any:
    """Runs `sssbake batch MANIFEST --out OUT --asset ASSET EXTRA --json` with
    `threads` threads (default: every core of the worker); returns what it
    printed."""
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    command = [sssbake, "batch", manifest, "--out", out, "--asset", asset, *extra, "--json"]
    result = subprocess.run(
        command,
        check=False,
        capture_output=True,
        text=True,
        env=env,
        preexec_fn=die_with_the_worker(),
    )
    if result.returncode not in (0, SOME_FAILED):
        last = (result.stderr.strip().splitlines() or ["no message"])[-1]
        raise FarmError(f"{asset}: sssbake exited with {result.returncode}: {last}")
    return json.loads(result.stdout)


def die_with_the_worker() -> Callable[[], None] | None:
    """What the bake's process runs before `sssbake` starts, on Linux: asks
    the kernel to kill it when the worker thread that started it dies, so a
    lost worker's bake does not go on writing beside the task's retry. The
    call is looked up here, in the worker, so the forked child only makes
    it."""
    if sys.platform != "linux":
        return None
    prctl = ctypes.CDLL(None, use_errno=True).prctl
    pr_set_pdeathsig = 1
    return lambda: prctl(pr_set_pdeathsig, signal.SIGKILL)


def bake_asset(sssbake: str, manifest: str, out: str, asset: str, threads: int | None) -> dict[str, Any]:
    """Bakes `asset` alone; returns the asset's report."""
    return sssbake_batch(sssbake, manifest, out, asset, [], threads)["assets"][0]


def bake_object(
    sssbake: str, manifest: str, out: str, asset: str, obj: str, threads: int | None
) -> dict[str, Any]:
    """Bakes object `obj` of `asset` into its part; returns the part's report."""
    return sssbake_batch(sssbake, manifest, out, asset, ["--object", obj], threads)


def assemble_asset(sssbake: str, manifest: str, out: str, asset: str) -> dict[str, Any]:
    """Builds `asset`'s folder from its parts; returns the asset's report
    (failed, naming the object, when a part failed or is missing)."""
    return sssbake_batch(sssbake, manifest, out, asset, ["--assemble"], None)["assets"][0]


def farm_tasks(sssbake: str, manifest: str, split_above: float | None) -> list[dict[str, Any]]:
    """Each asset's tasks as `sssbake batch --tasks` plans them: `objects`
    lists the objects of an asset split into one task per object."""
    command = [sssbake, "batch", manifest, "--tasks"]
    if split_above is not None:
        command += ["--split-above", repr(float(split_above))]
    result = subprocess.run(command, check=False, capture_output=True, text=True)
    if result.returncode != 0:
        last = (result.stderr.strip().splitlines() or ["no message"])[-1]
        raise FarmError(f"planning the tasks failed: {last}")
    return json.loads(result.stdout)


def run(
    manifest: str | os.PathLike[str],
    out: str | os.PathLike[str],
    client: Any,
    *,
    sssbake: str = "sssbake",
    threads_per_task: int | None = None,
    retries: int = 2,
    split_above: float | None = None,
) -> dict[str, Any]:
    """Bakes every asset of `manifest` into `out` on the cluster of
    `client` (a `distributed.Client`), one task per asset, or one per
    object and an assembly for an asset of several objects planned above
    `split_above` [sssbake's default, `sssbake batch --help`]; returns the
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

    # Local functions: pickle cannot send them by reference, so Dask sends
    # them (and this module) by value, and workers need only the binary.
    def asset_task(asset: str) -> dict[str, Any]:
        return bake_asset(sssbake, manifest, out, asset, threads_per_task)

    def object_task(asset: str, obj: str) -> dict[str, Any]:
        return bake_object(sssbake, manifest, out, asset, obj, threads_per_task)

    def assembly_task(asset: str, *parts: dict[str, Any]) -> dict[str, Any]:
        # The parts are the object tasks' reports: depending on them makes
        # the assembly wait for every object; it reads the parts from OUT.
        return assemble_asset(sssbake, manifest, out, asset)

    futures = []
    for tasks in farm_tasks(sssbake, manifest, split_above):
        name = tasks["asset"]
        if not tasks["objects"]:
            key = f"sssbake-{name}-{uuid.uuid4().hex}"
            futures.append(client.submit(asset_task, name, key=key, retries=retries, pure=False))
            continue
        parts = [
            client.submit(
                object_task,
                name,
                obj,
                key=f"sssbake-{name}/object-{i}-{uuid.uuid4().hex}",
                retries=retries,
                pure=False,
            )
            for i, obj in enumerate(tasks["objects"])
        ]
        key = f"sssbake-{name}/assemble-{uuid.uuid4().hex}"
        futures.append(client.submit(assembly_task, name, *parts, key=key, retries=retries, pure=False))
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
    """`sssbake-farm MANIFEST --out DIR --scheduler ADDRESS` (or `python -m
    sssbake.farm …`): runs the batch on the cluster at ADDRESS and prints its
    report; the exit code is sssbake's."""
    parser = argparse.ArgumentParser(
        prog="sssbake-farm", description="Run an sssbake batch on a Dask cluster."
    )
    parser.add_argument("manifest")
    parser.add_argument("--out", required=True, help="the batch's folder, on storage every worker shares")
    parser.add_argument("--scheduler", required=True, help="the Dask scheduler, such as tcp://host:8786")
    parser.add_argument("--sssbake", default="sssbake", help="the sssbake binary on the workers")
    parser.add_argument("--threads-per-task", type=int, help="threads of each bake [every core]")
    parser.add_argument(
        "--split-above",
        type=float,
        help="planned work above which an asset of several objects is one task per object [sssbake's default]",
    )
    args = parser.parse_args(argv)
    try:
        from distributed import Client
    except ImportError:
        print('sssbake-farm: the farm needs Dask: pip install "sssbake[farm]"', file=sys.stderr)
        return 2
    with Client(args.scheduler) as client:
        report = run(
            args.manifest,
            args.out,
            client,
            sssbake=args.sssbake,
            threads_per_task=args.threads_per_task,
            split_above=args.split_above,
        )
    print(json.dumps(report, indent=2))
    counts = report["counts"]
    return 0 if counts["failed"] == 0 and counts["missing"] == 0 else SOME_FAILED


if __name__ == "__main__":
    sys.exit(main())
