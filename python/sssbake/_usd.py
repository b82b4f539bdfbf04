"""A USD stage held in memory, read and written with this process's
usd-core through the same scripts the `sssbake` binary runs
(`usd/read_stage.py`, `usd/write_layer.py`, built into the native module):
no temporary file and no second Python."""

from __future__ import annotations

import importlib.util
import json
import types
from typing import Any

from . import _native
from .errors import InputError, OutputError

EXTENSIONS = (".usd", ".usda", ".usdc", ".usdz")
"""The scene files read as USD."""


def has_usd() -> bool:
    """True when this Python has usd-core."""
    return importlib.util.find_spec("pxr") is not None


def open_stage(path: str) -> Any:
    """The stage in the USD file `path`, opened as the `sssbake` binary opens it."""
    reader = _script("read_stage")
    try:
        return reader.open_stage(path)
    except reader.StageError as e:
        raise InputError(str(e), file=path) from None


def _module(name: str, source: str) -> types.ModuleType:
    module = types.ModuleType(f"sssbake._{name}")
    exec(compile(source, f"<sssbake {name}.py>", "exec"), module.__dict__)  # noqa: S102 - our own script
    return module


_scripts: dict[str, types.ModuleType] = {}


def _script(name: str) -> types.ModuleType:
    """The script `name` loaded once as a module (its imports of pxr happen then)."""
    if name not in _scripts:
        source = {"read_stage": _native.READ_STAGE, "write_layer": _native.WRITE_LAYER}[name]
        _scripts[name] = _module(name, source)
    return _scripts[name]


def is_stage(scene: Any) -> bool:
    """True for a `pxr.Usd.Stage` (checked by its interface, so pxr is imported only when used)."""
    return hasattr(scene, "GetRootLayer") and hasattr(scene, "Traverse")


def stage_name(stage: Any) -> str:
    """What errors and the bake call the stage: its root layer's file, or for a
    layer only in memory `<in memory>/TAG` (TAG as given to `CreateInMemory`,
    `tmp.usda` by default), whose stem names the layer the bake writes."""
    layer = stage.GetRootLayer()
    if layer.realPath:
        return layer.realPath
    tag = layer.identifier.rsplit(":", 1)[-1] or "stage.usda"
    return f"<in memory>/{tag}"


def stage_json(stage: Any, uv_set: int) -> str:
    """The stage's meshes, materials and lights as the reader's JSON."""
    reader = _script("read_stage")
    try:
        return reader.stage_json(stage, _native.uv_primvars(uv_set))
    except reader.StageError as e:
        raise InputError(str(e), file=stage_name(stage)) from None


def layer_writer(stage: Any):
    """The callable the bake writes the stage's layer with, over `stage` itself."""
    writer = _script("write_layer")

    def write(request_json: str) -> str:
        try:
            return writer.layer_text(stage, json.loads(request_json))
        except writer.LayerError as e:
            raise OutputError(str(e), file=stage_name(stage)) from None

    return write


def add_sublayer(target: Any, layer_path: str) -> None:
    """Puts the layer at `layer_path` first (strongest) among the sublayers of
    `target`, a stage (its root layer) or a layer, unless it is there already."""
    layer = target.GetRootLayer() if is_stage(target) else target
    paths = list(layer.subLayerPaths)
    if layer_path not in paths:
        layer.subLayerPaths.insert(0, layer_path)
