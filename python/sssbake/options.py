"""The options `sssbake.bake`, `plan` and `batch` take as keywords, and a batch
manifest's tables: every setting of the library (`sssbake.settings()`), typed.

Generated from the library by tests/test_settings.py (SSSBAKE_UPDATE_DOCS=1); do not edit.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Literal, TypedDict


class Options(TypedDict, total=False):
    """Each option left out keeps the library's default."""

    objects: Sequence[str]
    """Objects to bake, by name (default: every object)."""
    preset: Literal[
        "apple",
        "chicken1",
        "chicken2",
        "cream",
        "ketchup",
        "marble",
        "potato",
        "skimmilk",
        "skin1",
        "skin2",
        "spectralon",
        "wholemilk",
        "wax",
        "dilutedmilk",
        "orangejuice",
        "lozenge",
        "skin3layer",
        "two-slab",
        "stam-skin",
        "deon-skin",
    ]
    """A material preset for every object the sidecar does not name (default: the object's own material in the file, else skin1)."""
    material: str | os.PathLike[str]
    """A TOML material file for every object the sidecar does not name (default: none)."""
    materials: str | os.PathLike[str]
    """A TOML sidecar naming each object's preset or material file (default: none)."""
    model: Literal["dipole", "multipole", "layered", "gaussians", "burley", "montecarlo", "stam", "empirical"]
    """The profile model (default: chosen for the material)."""
    resolution: int
    """Texels per side of each map (1 to 16384 texels; default: 1024)."""
    uv_set: int
    """The texture-coordinate set to bake into (0 to 255; default: 0)."""
    uvs: Literal["auto", "unwrap", "keep"]
    """What to do with the objects' UVs: `auto` unwraps with xatlas where they are not usable, `unwrap` always, `keep` bakes into them as they are (default: auto)."""
    margin: int
    """Texels filled beyond each chart's edge, and between the charts of an unwrap (0 to 16384 texels; default: 8)."""
    outputs: Sequence[Literal["subsurface", "irradiance", "diffuse", "thickness", "stretch", "area"]]
    """The maps to make (default: subsurface,irradiance,diffuse)."""
    method: Literal["auto", "brute", "octree", "texture", "importance", "walk"]
    """The integrator, or `auto` to let the library choose and say why (default: auto)."""
    octree_epsilon: float
    """Octree: the solid angle below which a node is taken whole (at least 0 sr; default: 0.5)."""
    gaussians: int
    """Texture space: Gaussians in the fit (and in a `gaussians` model) (1 to 16 Gaussians; default: 6)."""
    samples: int
    """Importance: probes per texel (at least 1 probes per texel; default: 512)."""
    walk_samples: int
    """Walk: walks per texel and channel (2 to 1048576 walks per texel; default: 256)."""
    seed: int
    """Seed of the Monte Carlo of importance sampling and of the walk (at least 0; default: 1)."""
    unit_scale: float
    """Millimetres per scene unit, overriding the file's units (above 0 mm per scene unit; default: the file's own units)."""
    irradiance: str | os.PathLike[str]
    """An image (.exr linear, .png sRGB) in the objects' UV layout used as the transmitted irradiance instead of the scene's lights (default: the scene's lights)."""
    environment: str | os.PathLike[str]
    """An equirectangular image (.exr) for the scene's environment light (default: the scene's own)."""
    base_color: str | os.PathLike[str]
    """A base colour image (.exr linear, .png sRGB) in the objects' UVs, applied as C^α before scattering and C^(1−α) after (default: the material's colour)."""
    colour_split: float
    """α of the colour split (Mikkelsen §3.5): 0 colours after scattering only, 1 before only (0 to 1; default: 0.5)."""
    light_samples: int
    """Samples per soft light and for the environment, per texel (at least 1 samples per texel; default: 16)."""
    bounces: int
    """Bounces of the light each object sends onto itself across air (an eye socket, a fold, an ear), as a path tracer's diffuse bake carries it; 0 bakes the direct light alone (0 to 16 bounces; default: 3)."""
    roughness: float
    """RMS facet slope of every material's surface (Donner & Jensen 2005 §2.4) (0 to 1 RMS slope; default: each material's own)."""
    tolerance: float
    """Relative RMSE against the exact sum that `auto` holds each object to: it estimates its error and moves to a more exact method above it (0.01 is 1%) (above 0 relative RMSE; default: 0.01)."""
    light_check: int
    """Texels at which the bake is checked against light itself, a volumetric random walk through the mesh, reported beside the error against the exact sum (0 turns the check off) (0 to 65536 texels; default: 256)."""
    max_memory: str
    """Memory a bake may hold (16G, 512M: binary units); the plan refuses a bake estimated to need more (a size such as 16G or 512M; default: 16G)."""
    max_evaluations: float
    """Shadow rays, kernel evaluations and probes a bake may take (3e10 is about an hour of the exact sum on two cores); the plan refuses more (above 0 evaluations; default: 3e10)."""
    half: bool
    """Write EXRs as 16-bit half floats instead of 32-bit (default: false)."""
    exposure: float
    """Exposure of the PNG previews (the EXRs stay as baked) (stops; default: 0)."""
