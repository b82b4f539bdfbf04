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
