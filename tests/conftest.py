"""Shared fixtures: the sssbake binary the tests run."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent


@pytest.fixture(scope="session")
def sssbake() -> pathlib.Path:
    """The release binary: $SSSBAKE_BIN, or target/release/sssbake."""
    path = pathlib.Path(os.environ.get("SSSBAKE_BIN", ROOT / "target" / "release" / "sssbake"))
    if not path.exists():
        raise FileNotFoundError(f"{path}: build it with `cargo build --release -p sssbake-cli`")
    return path


def run(binary: pathlib.Path, *args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    """Runs the binary, capturing text output, with `env` added to the environment."""
    return subprocess.run(
        [str(binary), *args],
        check=False,
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, **(env or {})},
    )


def exr(path):
    """An RGB EXR map as a float array, rows top to bottom."""
    import OpenEXR

    return OpenEXR.File(str(path)).parts[0].channels["RGB"].pixels


def bake_summary(binary: pathlib.Path, scene: pathlib.Path, out: pathlib.Path, *args: str) -> dict:
    """Bakes `scene` into `out` with `args` (USD read by this Python) and returns the summary."""
    import json
    import sys

    result = run(
        binary,
        "bake",
        str(scene),
        "--out",
        str(out),
        "--json",
        *args,
        env={"SSSBAKE_PYTHON": sys.executable},
    )
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def usd_validation_errors(stage) -> list[str]:
    """usd-core's validators' messages for `stage`, less one kind: usd-core is built
    without MaterialX, so its shader registry does not know MaterialX node ids (`ND_…`,
    such as the examples' OpenPBR shaders), which a MaterialX-enabled USD resolves."""
    from pxr import UsdValidation

    registry = UsdValidation.ValidationRegistry()
    context = UsdValidation.ValidationContext(registry.GetOrLoadAllValidators())
    messages = [error.GetMessage() for error in context.Validate(stage)]
    return [m for m in messages if not ("shaderId 'ND_" in m and "not found in sdrRegistry" in m)]
