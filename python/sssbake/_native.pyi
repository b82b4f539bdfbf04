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
def settings() -> str: ...
def report(
    input: str,
    out: str,
    options_json: str,
    force: bool,
    stage_json: str | None = None,
    progress: Callable[[float, str], object] | None = None,
    cancel: Any | None = None,
) -> str: ...
def profile_plot(
    preset: str | None = None,
    material: str | None = None,
    model: str | None = None,
    radii: list[float] | None = None,
    epsilon: float = 1e-3,
    gaussians: int = 6,
    compare_montecarlo: bool = False,
    photons: int = 100_000,
    seed: int = 1,
) -> str: ...
def uv_primvars(uv_set: int) -> list[str]: ...
def profile(
    preset: str | None = None,
    material: str | None = None,
    model: str | None = None,
    radii: list[float] | None = None,
    epsilon: float = 1e-3,
    gaussians: int = 6,
    photons: int = 100_000,
    seed: int = 1,
) -> dict[str, Any]: ...
def unwrap(name: str, positions: Any, indices: Any, resolution: int, padding: int) -> tuple[Any, Any]: ...
def defaults() -> str: ...

class BakeResult:
    @property
    def resolution(self) -> int: ...
    @property
    def summary(self) -> str: ...
    def image(self, output: str) -> Any: ...
    def write_exr(self, output: str, path: str, half: bool = False) -> None: ...

class Scene:
    def __init__(self, millimetres_per_unit: float) -> None: ...
    def objects(self) -> list[str]: ...
    def add_mesh(
        self,
        name: str,
        positions: Any,
        indices: Any,
        normals: Any | None = None,
        uvs: Any | None = None,
        material_indices: Any | None = None,
        texture_uvs: list[Any] = ...,
    ) -> None: ...
    def add_light(self, light_json: str) -> None: ...
    def set_world(self, colour: tuple[float, float, float], strength: float) -> None: ...
    def bake_object(
        self,
        object: str,
        materials_json: str,
        images: list[Any | None],
        options_json: str,
        progress: Callable[[float, str], object] | None = None,
        cancel: Any | None = None,
    ) -> BakeResult: ...
    def bake(
        self,
        out: str,
        options_json: str,
        force: bool,
        progress: Callable[[float, str], object] | None = None,
        cancel: Any | None = None,
    ) -> str: ...
