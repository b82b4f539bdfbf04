"""Scenes a host builds from its own arrays: meshes (numpy), lights in Blender's terms
and a world, baked object by object into maps held in memory (with a material per face
slot: Principled BSDF inputs and a base-colour image, a preset, a TOML material, or no
subsurface), or whole into a folder.

    import numpy as np, sssbake
    scene = sssbake.Scene(millimetres_per_unit=1000.0)           # a scene in metres
    scene.add_mesh("Plane", positions, indices, uvs=uvs)         # flat float32 / uint32 arrays
    scene.add_light("sun", power=3.0, direction=(0, 0, -1))
    result = scene.bake_object("Plane", [{"kind": "preset", "name": "skin1"}], resolution=64)
    rgba = result.image("subsurface")                            # (64, 64, 4), rows from v = 0 up

Lengths are in scene units; the scene converts them with its millimetres per unit.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any, Protocol, Unpack

import numpy as np

from . import _native
from ._options import options_json
from .options import Options


class CancelEvent(Protocol):
    """What `cancel` must offer: `threading.Event` does."""

    def is_set(self) -> bool: ...


Progress = Callable[[float, str], object]

Material = Mapping[str, Any]
"""A material of an object's bake, as a dict:

- `{"kind": "principled", "name": ..., <inputs>}`: Blender's Principled BSDF
  subsurface inputs (`base_colour`, `subsurface_weight`, `radius`, `scale` in scene
  units, `ior`, `anisotropy`, `method` BURLEY, RANDOM_WALK or RANDOM_WALK_SKIN,
  `subsurface_ior`, `specular_ior_level`, `albedo` cycles or physical, `roughness`);
  inputs left out take Blender's defaults. Read as Cycles reads them.
- `{"kind": "preset", "name": "skin1"}`; `{"kind": "toml", "toml": text, "name": ...}`.
- `{"kind": "none", "name": ...}`: no subsurface; its faces are left out, texels empty.

Any of them may carry `"image"`: `{"pixels": array (height, width, 3 or 4) or flat,
"width", "height", "channels", "uv_set", "extension" (REPEAT, EXTEND, CLIP, MIRROR),
"nearest", "name"}`, linear texels with rows from v = 0 up, read through UV set
`uv_set` (0 the mesh's `uvs`, k the k-th of its `texture_uvs`).
"""


def _floats(values: Any) -> np.ndarray:
    return np.ascontiguousarray(values, dtype=np.float32).reshape(-1)


def _indices(values: Any) -> np.ndarray:
    return np.ascontiguousarray(values, dtype=np.uint32).reshape(-1)


class BakeResult:
    """One object's bake: its `summary` (what `sssbake bake --json` says of it) and its
    maps, each `resolution`² texels."""

    def __init__(self, native: _native.BakeResult) -> None:
        self._native = native
        self.summary: dict[str, Any] = json.loads(native.summary)

    @property
    def resolution(self) -> int:
        """Texels per side."""
        return self._native.resolution

    def image(self, output: str) -> np.ndarray:
        """Map `output` (`subsurface`, `irradiance`, `diffuse`, `thickness`, `stretch`,
        `area`; units as docs/outputs.md gives them) as a float32 (n, n, 4) RGBA array,
        rows from v = 0 up, alpha 1 on covered and filled texels, 0 elsewhere."""
        n = self.resolution
        return self._native.image(output).reshape(n, n, 4)

    def write_exr(self, output: str, path: str | os.PathLike[str], *, half: bool = False) -> None:
        """Writes map `output` as a linear OpenEXR file (32-bit, or 16-bit when `half`),
        the bytes `sssbake bake` writes, whole or not at all."""
        self._native.write_exr(output, os.fspath(path), half)


class Scene:
    """A scene built from a host's arrays, `millimetres_per_unit` mm to its unit."""

    def __init__(self, millimetres_per_unit: float = 1.0) -> None:
        self._native = _native.Scene(float(millimetres_per_unit))

    @property
    def objects(self) -> list[str]:
        """The objects' names, in the order they were added."""
        return self._native.objects()

    def add_mesh(
        self,
        name: str,
        positions: Any,
        indices: Any,
        *,
        normals: Any | None = None,
        uvs: Any | None = None,
        material_indices: Any | None = None,
        texture_uvs: Iterable[Any] = (),
    ) -> None:
        """Adds a mesh as the object `name`: `positions` (x, y, z per vertex, world
        space), optional unit `normals`, optional `uvs` (u, v per vertex, v running up;
        without them the bake unwraps), `indices` (three per triangle, counter-clockwise
        seen from outside), optionally a `material_indices` entry per triangle (into the
        materials of `bake_object`) and further `texture_uvs` sets images may read.
        Vertices equal in every attribute are shared, so one vertex per corner is fine."""
        self._native.add_mesh(
            name,
            _floats(positions),
            _indices(indices),
            None if normals is None else _floats(normals),
            None if uvs is None else _floats(uvs),
            None if material_indices is None else _indices(material_indices),
            [_floats(s) for s in texture_uvs],
        )

    def add_light(self, kind: str, **fields: Any) -> None:
        """Adds a light in Blender's terms (docs/lights.md, the Blender light table): `kind`
        sun, point, spot, rectangle or disk, and any of `colour`, `power` (W, or a sun's
        W/m²), `position`, `direction` (where it shines), `tangent` (its X axis), `size`,
        `size_y`, `angle`, `spot_size`, `spot_blend`, `exposure`, `temperature_colour`,
        `diffuse_factor`, `spread`, `normalize`, `casts_shadow`; the rest take Blender's
        defaults."""
        plain = {k: (list(v) if isinstance(v, (tuple, np.ndarray)) else v) for k, v in fields.items()}
        self._native.add_light(json.dumps({"kind": kind, **plain}, default=float))

    def set_world(self, colour: Sequence[float], strength: float) -> None:
        """A uniform world: `colour` × `strength`, a radiance in W/(m²·sr) (Blender's
        Background); black or 0 removes it."""
        r, g, b = (float(c) for c in colour)
        self._native.set_world((r, g, b), float(strength))

    def bake_object(
        self,
        name: str,
        materials: Sequence[Material],
        *,
        progress: Progress | None = None,
        cancel: CancelEvent | None = None,
        **options: Unpack[Options],
    ) -> BakeResult:
        """Bakes object `name`, each face with the material its material index names
        (all with the first when the mesh gives none or one material is given), into its
        own UVs as they are (`uvs="auto"` unwraps where unusable). `options` are
        `sssbake.bake`'s (`resolution`, `method`, `outputs`, `margin`, `light_samples`,
        `tolerance`, ...), less the materials and the file's units. A texel shows the bake
        of its own face's material; the summary lists each material's texels."""
        specs, images = [], []
        for material in materials:
            spec = dict(material)
            image = spec.get("image")
            if image is not None:
                image = dict(image)
                images.append(_floats(image.pop("pixels")))
                spec["image"] = image
            else:
                images.append(None)
            specs.append(spec)
        native = self._native.bake_object(
            name, json.dumps(specs, default=float), images, options_json(options), progress, cancel
        )
        return BakeResult(native)

    def bake(
        self,
        out: str | os.PathLike[str],
        *,
        force: bool = False,
        progress: Progress | None = None,
        cancel: CancelEvent | None = None,
        **options: Unpack[Options],
    ) -> dict[str, Any]:
        """Bakes every object (or `objects`) into the folder `out` as `sssbake.bake`
        bakes a file, with its options (`preset`, `material` or `materials` for the
        materials, skin1 otherwise), and returns the summary; the maps are written, whole
        or not at all (a host's scene has no file for a glTF copy or USD layer)."""
        return json.loads(self._native.bake(os.fspath(out), options_json(options), force, progress, cancel))


def unwrap(
    name: str, positions: Any, indices: Any, resolution: int, padding: int
) -> tuple[np.ndarray, np.ndarray]:
    """UVs from the library's xatlas, as a bake unwraps: charts for a `resolution`² map,
    `padding` texels apart. Returns the UV of each index (float32, 2 per index, v
    running up) and each triangle's chart number (uint32)."""
    return _native.unwrap(name, _floats(positions), _indices(indices), int(resolution), int(padding))


def defaults() -> dict[str, Any]:
    """The library's defaults a host shows in its settings (`resolution`, `margin`,
    `light_samples`, `tolerance`, `max_memory_bytes`, `method`, `outputs`, and `preset`, the one a
    bake falls back on), every output's and method's
    name (`all_outputs`, `all_methods`), and the presets a bake can use (`presets`, pairs of
    name and description)."""
    return json.loads(_native.defaults())
