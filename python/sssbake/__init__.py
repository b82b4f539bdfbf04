"""sssbake from Python: subsurface scattering baked into textures.

    import sssbake
    summary = sssbake.bake("examples/head/head.gltf", "baked", resolution=256)
    print(summary["objects"][0]["accuracy"]["method"], summary["files"])

`bake`, `plan` and `batch` take the options of a batch manifest's tables
(docs/pipelines.md: `resolution`, `preset`, `material`, `method`,
`tolerance`, `max_memory`, ...) as keyword arguments and return what the
command line prints with `--json`, as dicts. A scene is a file (glTF or USD)
or a `pxr.Usd.Stage` held in memory; USD is read and written with this
Python's usd-core (`pip install sssbake[usd]`). The library runs with the GIL released;
`progress(fraction, stage)` is called about ten times a second, and setting
a `threading.Event` passed as `cancel` (or Ctrl-C) stops the work with
`sssbake.errors.Cancelled`. Errors are `sssbake.errors.Error` subclasses
carrying the library's kind, message, file, object and field.

`sssbake.Scene` is a scene built from a host's own arrays (numpy meshes, lights in
Blender's terms, Principled materials with images, faces in material slots), baked
object by object into maps in memory or whole into a folder (`sssbake.host`).

`sssbake.farm` runs a batch on a Dask cluster.
"""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any, Protocol, Unpack

from . import _native, _usd
from ._options import options_json
from .errors import Cancelled, Error, InputError, OutputError, SettingError
from .host import BakeResult, Scene, defaults, unwrap
from .options import Options

__all__ = [
    "BakeResult",
    "Cancelled",
    "Error",
    "InputError",
    "Options",
    "OutputError",
    "Scene",
    "SettingError",
    "__version__",
    "bake",
    "batch",
    "defaults",
    "plan",
    "presets",
    "profile",
    "profile_plot",
    "report",
    "settings",
    "unwrap",
]

__version__: str = _native.VERSION

SceneFile = str | os.PathLike[str] | Any
"""A scene file's path, or a `pxr.Usd.Stage`."""


class CancelEvent(Protocol):
    """What `cancel` must offer: `threading.Event` does."""

    def is_set(self) -> bool: ...


Progress = Callable[[float, str], object]
"""Called with the fraction done in [0, 1] (rising, 1 at the end) and the stage's label."""


def _source(scene: SceneFile, options: Mapping[str, Any]) -> tuple[str, Any | None]:
    """The scene's name for the library and, for USD, the open stage: a stage
    given, or a USD file opened with this Python's usd-core when it has one."""
    if _usd.is_stage(scene):
        return _usd.stage_name(scene), scene
    name = os.fspath(scene)
    if Path(name).suffix.lower() in _usd.EXTENSIONS and Path(name).is_file() and _usd.has_usd():
        return name, _usd.open_stage(name)
    return name, None


def _contents(stage: Any | None, options: Mapping[str, Any]) -> str | None:
    return None if stage is None else _usd.stage_json(stage, int(options.get("uv_set") or 0))


def bake(
    scene: SceneFile,
    out: str | os.PathLike[str],
    *,
    force: bool = False,
    progress: Progress | None = None,
    cancel: CancelEvent | None = None,
    look_on: Any | None = None,
    **options: Unpack[Options],
) -> dict[str, Any]:
    """Bakes `scene` into the folder `out` as `sssbake bake --json` does and
    returns its summary: per object the plan, the method and its estimated
    error, seconds per stage, and `files`, every file written.

    Maps already in `out` are kept unless `force`. For a USD scene the bake
    writes a layer `<name>_sssbake.usda` showing the look: over the scene's
    file, or for a stage only in memory a layer of overrides alone.
    `look_on` (a `pxr.Usd.Stage` or `pxr.Sdf.Layer`) then gets that layer as
    its strongest sublayer, so the stage shows the baked look at once.
    """
    name, stage = _source(scene, options)
    if look_on is not None and stage is None:
        raise SettingError(
            f"{name}: only a USD scene gets a layer to add (a stage, or a USD file with usd-core)",
            field="look_on",
        )
    summary = json.loads(
        _native.bake(
            name,
            os.fspath(out),
            options_json(options),
            force,
            _contents(stage, options),
            None if stage is None else _usd.layer_writer(stage),
            progress,
            cancel,
        )
    )
    if look_on is not None:
        layers = [f for f in summary["files"] if f.endswith("_sssbake.usda")]
        if not layers:
            raise SettingError(
                "the bake wrote no USD layer to add (a USD scene with the `look` output makes one)",
                field="look_on",
            )
        _usd.add_sublayer(look_on, str(Path(layers[0]).resolve()))
    return summary


def plan(scene: SceneFile, **options: Unpack[Options]) -> dict[str, Any]:
    """The plan `bake` with these options would run, as `sssbake plan --json`
    prints it: per object the material, model, resolution, UV decision,
    method and why, and the estimated cost; nothing is baked."""
    name, stage = _source(scene, options)
    return json.loads(_native.plan(name, options_json(options), _contents(stage, options)))


def report(
    scene: SceneFile,
    out: str | os.PathLike[str],
    *,
    force: bool = False,
    progress: Progress | None = None,
    cancel: CancelEvent | None = None,
    **options: Unpack[Options],
) -> dict[str, Any]:
    """Runs every integrator on `scene` across a ladder of settings, each against the exact
    sum, as `sssbake report` does: writes report.json, report.csv, report.svg and
    report.png (error against run time) and an error map per method into the folder `out`,
    and returns report.json as a dict (`runs`: method, setting, seconds, relative_rmse,
    max_error, and `pareto` for the runs no other beats on both time and error). A report
    already in `out` is kept unless `force`."""
    name, stage = _source(scene, options)
    return json.loads(
        _native.report(
            name, os.fspath(out), options_json(options), force, _contents(stage, options), progress, cancel
        )
    )


def profile_plot(
    preset: str | None = None,
    *,
    material: str | os.PathLike[str] | None = None,
    model: str | None = None,
    radii: Iterable[float] | None = None,
    epsilon: float = 1e-3,
    gaussians: int = 6,
    compare_montecarlo: bool = False,
    photons: int = 100_000,
    seed: int = 1,
) -> str:
    """The plot of `profile`'s R(r) and r·R(r) per channel as SVG text, as `sssbake profile
    --plot` draws it; with `compare_montecarlo`, the Monte Carlo reference (`photons` per
    channel, `seed`) beside it."""
    return _native.profile_plot(
        preset,
        None if material is None else os.fspath(material),
        model,
        None if radii is None else [float(r) for r in radii],
        epsilon,
        gaussians,
        compare_montecarlo,
        photons,
        seed,
    )


def profile(
    preset: str | None = None,
    *,
    material: str | os.PathLike[str] | None = None,
    model: str | None = None,
    radii: Iterable[float] | None = None,
    epsilon: float = 1e-3,
    gaussians: int = 6,
    photons: int = 100_000,
    seed: int = 1,
) -> dict[str, Any]:
    """A material's reflectance profile (a preset by name, or a TOML
    material file) under `model` (the material's own by default), as numpy
    arrays: `radii_mm` (N,), `reflectance` and `transmittance` (N, 3) in
    1/mm², `total_reflectance`, `total_transmittance` and `d_max_mm` (3,),
    d_max keeping all but `epsilon` of the reflectance. `radii` (mm) must
    increase; without them, sixty radii spaced evenly in ln r over the
    profile's reach. The `montecarlo` model simulates `photons` per channel
    from `seed`. The same profile `sssbake profile` prints."""
    return _native.profile(
        preset,
        None if material is None else os.fspath(material),
        model,
        None if radii is None else [float(r) for r in radii],
        epsilon,
        gaussians,
        photons,
        seed,
    )


def batch(
    manifest: str | os.PathLike[str],
    out: str | os.PathLike[str],
    *,
    force: bool = False,
    jobs: int = 1,
    assets: Iterable[str] = (),
    on_asset: Callable[[dict[str, Any]], object] | None = None,
) -> dict[str, Any]:
    """Runs a batch manifest as `sssbake batch --json` does and returns the
    batch report; assets unchanged since their last bake are skipped unless
    `force`. `on_asset` gets each asset's report as it ends. A failed asset
    is reported in the result (`counts["failed"]`), not raised."""
    # USD assets are read by the scripts in a Python with usd-core: this one.
    os.environ.setdefault("SSSBAKE_PYTHON", sys.executable)
    callback = None if on_asset is None else (lambda text: on_asset(json.loads(text)))
    return json.loads(_native.batch(os.fspath(manifest), os.fspath(out), force, jobs, list(assets), callback))


def settings() -> list[dict[str, Any]]:
    """Every bake setting, as the library defines it: `name` (the keyword), `doc`, `kind`
    (`count`, `number`, `switch`, `choice`, `choices`, `names`, `file`, `size`) with its
    range (`min`, `max`, `min_exclusive`) or `names`, `unit`, `part` (`scene`, `bake`,
    `writing`, or `{"integrator": method}`), `default` (None where there is none to state)
    and `default_text`. `sssbake.options.Options` types them as keywords."""
    return json.loads(_native.settings())


def presets() -> dict[str, str]:
    """Every material preset's name with a line on what it is."""
    return dict(_native.presets())
