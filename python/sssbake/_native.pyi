"""Type hints of the native module (rust/python); use the functions of `sssbake` instead."""

from collections.abc import Callable
from typing import Any

VERSION: str
READ_STAGE: str
WRITE_LAYER: str

def bake(
    input: str,
    out: str,
    options_json: str,
    force: bool,
    stage_json: str | None = None,
    layer_writer_callable: Callable[[str], str] | None = None,
    progress: Callable[[float, str], object] | None = None,
    cancel: Any | None = None,
) -> str: ...
def plan(input: str, options_json: str, stage_json: str | None = None) -> str: ...
def batch(
    manifest: str,
    out: str,
    force: bool = False,
    jobs: int = 1,
    assets: list[str] = ...,
    on_asset: Callable[[str], object] | None = None,
) -> str: ...
def presets() -> list[tuple[str, str]]: ...
def uv_primvars(uv_set: int) -> list[str]: ...
def profile(
    preset: str | None = None,
    material: str | None = None,
    model: str | None = None,
    radii: list[float] | None = None,
    epsilon: float = 1e-3,
    gaussians: int = 6,
) -> dict[str, Any]: ...
