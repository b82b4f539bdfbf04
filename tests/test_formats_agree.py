"""Each bundled example is one Blender scene exported to glTF and to USD, with one material
stated by each format's own definition (glTF volume with KHR_materials_ior, OpenPBR): both
files must give the same light and the same subsurface map. (They still differ by the sun's
angular size, which glTF cannot carry.)"""

import numpy as np
import pytest
from conftest import ROOT, bake_summary, exr


def maps(sssbake, scene, out):
    summary = bake_summary(sssbake, scene, out, "--resolution", "64", "--outputs", "irradiance,subsurface")
    return {
        (o["name"], output): exr(out / f"{o['file_stem']}_{output}.exr")
        for o in summary["objects"]
        for output in ("irradiance", "subsurface")
    }


@pytest.mark.parametrize("name", ["head", "marble", "ear"])
def test_the_gltf_and_usd_exports_of_an_example_bake_the_same_maps(sssbake, name, tmp_path):
    folder = ROOT / "examples" / name
    from_gltf = maps(sssbake, folder / f"{name}.gltf", tmp_path / "gltf")
    from_usd = maps(sssbake, folder / f"{name}.usda", tmp_path / "usd")
    assert from_gltf.keys() == from_usd.keys() and from_gltf
    for key, gltf in from_gltf.items():
        usd = from_usd[key]
        level = gltf[..., :3].mean(axis=-1)
        lit = level > 0.05 * level.max()
        assert lit.sum() > 100, key
        ratio = usd[lit][:, :3] / gltf[lit][:, :3]
        # The light within 1%; what scatters within 2%: at skin's reach the ear's red gathers
        # from the whole of it, and is raised where its surface ends by the sums of the two
        # exports' own triangles (measured: 0.985).
        tolerance = 0.01 if key[1] == "irradiance" else 0.02
        assert np.median(ratio, axis=0) == pytest.approx(1.0, abs=tolerance), (key, np.median(ratio, axis=0))
