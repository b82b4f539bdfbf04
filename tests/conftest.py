"""Shared fixtures: the sssbake binary the tests run, and the Blender add-on."""

import gc
import os
import pathlib
import struct
import subprocess
import sys
import zlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent

# The binary reads USD through $SSSBAKE_PYTHON; this one has usd-core. Every process the
# tests start inherits it (the batch's farm workers too); a test that wants another passes
# its own.
os.environ.setdefault("SSSBAKE_PYTHON", sys.executable)


# The repository the tests load the add-on from, as Blender loads an extension of a
# repository: `bl_ext.<repository>.sssbake`.
REPOSITORY = "sssbake_tests"


def load_extension(name: str, folder: pathlib.Path, repository: str = REPOSITORY):
    """Imports the extension in `folder`/`name` as Blender does, as
    `bl_ext.<repository>.<name>`, so its `import sssbake` is the Python package (which
    Blender installs from the extension's wheels), not the add-on itself."""
    import importlib
    import types

    if "bl_ext" not in sys.modules:
        namespace = types.ModuleType("bl_ext")
        namespace.__path__ = []
        sys.modules["bl_ext"] = namespace
    parent = types.ModuleType(f"bl_ext.{repository}")
    parent.__path__ = [str(folder)]
    sys.modules[parent.__name__] = parent
    _take_modules(f"{parent.__name__}.{name}")
    return importlib.import_module(f"{parent.__name__}.{name}")


@pytest.fixture
def addon():
    """The Blender add-on registered from blender_addon/ in a factory-fresh headless bpy,
    loaded as Blender loads the extension, baking through the `sssbake` package."""
    import bpy

    # Python objects wrapping the last test's Blender data are freed here, on the main
    # thread, before the factory settings free the data they point at.
    gc.collect()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    module = load_extension("sssbake", ROOT / "blender_addon")
    module.register()
    yield module
    module.unregister()
    _take_modules(module.__name__)
    gc.collect()


def _take_modules(name: str) -> dict:
    """Removes module `name` and its submodules from sys.modules; returns them."""
    taken = {k: m for k, m in sys.modules.items() if k == name or k.startswith(name + ".")}
    for key in taken:
        del sys.modules[key]
    return taken


@pytest.fixture(scope="session")
def sssbake() -> pathlib.Path:
    """The release binary: $SSSBAKE_BIN, or target/release/sssbake."""
    path = pathlib.Path(os.environ.get("SSSBAKE_BIN", ROOT / "target" / "release" / "sssbake"))
    if not path.exists():
        raise FileNotFoundError(f"{path}: build it with `cargo build --release -p sssbake-cli`")
    return path


@pytest.fixture(scope="module")
def client():
    """A Dask LocalCluster of two single-threaded worker processes, shared by
    a module's farm tests (starting one takes seconds) and closed after them:
    its threads must not outlive them into the Blender tests, where a garbage
    collection run on one of them could free Blender's data off the main
    thread."""
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
    )
    with distributed.Client(cluster) as client:
        yield client
    cluster.close()


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


def srgb_to_linear(encoded):
    """sRGB-encoded values in [0, 1] as linear ones."""
    import numpy

    encoded = numpy.asarray(encoded, dtype=numpy.float64)
    return numpy.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4)


def png_rgb(path: pathlib.Path):
    """An 8-bit RGB, non-interlaced PNG's codes, rows top to bottom (the encoding the
    writer uses; anything else fails here)."""
    import numpy

    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    position, header, compressed = 8, None, b""
    while position < len(data):
        (length,) = struct.unpack(">I", data[position : position + 4])
        kind = data[position + 4 : position + 8]
        body = data[position + 8 : position + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            compressed += body
        position += 12 + length
    width, height, depth, colour, _, _, interlace = header
    assert (depth, colour, interlace) == (8, 2, 0), header
    raw = zlib.decompress(compressed)
    stride = width * 3
    rows, previous = [], [0] * stride
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], raw[start + 1 : start + 1 + stride]
        row = list(line)
        for x in range(stride) if kind else ():
            left = row[x - 3] if x >= 3 else 0
            up = previous[x]
            if kind == 1:
                predicted = left
            elif kind == 2:
                predicted = up
            elif kind == 3:
                predicted = (left + up) // 2
            else:
                corner = previous[x - 3] if x >= 3 else 0
                estimate = left + up - corner
                pa, pb, pc = abs(estimate - left), abs(estimate - up), abs(estimate - corner)
                predicted = left if pa <= pb and pa <= pc else (up if pb <= pc else corner)
            row[x] = (line[x] + predicted) & 255
        rows.append(row)
        previous = row
    return numpy.array(rows, dtype=numpy.int64).reshape(height, width, 3)


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
