"""Prints every file a USD stage reads: its layers (sublayers, references,
payloads) and the assets they name (textures), one path a line; a path
usd-core could not resolve is printed after a `?`.

Run by sssbake's batch (rust/io/src/batch/fingerprint.rs) with the file as
the only argument, to know what a bake of it depends on."""

import sys

from pxr import UsdUtils


def main(path: str) -> None:
    layers, assets, unresolved = UsdUtils.ComputeAllDependencies(path)
    for layer in layers:
        print(layer.realPath or layer.identifier)
    for asset in assets:
        print(asset)
    for missing in unresolved:
        print(f"?{missing}")


if __name__ == "__main__":
    main(sys.argv[1])
