"""USD stages broken one way at a time, baked by the binary through the usd-core reader:
each is refused with exit 1 and a message naming the file, the prim and what is wrong;
no output folder is made and the stage is byte for byte as it was."""

import pytest
from conftest import run

HEADER = "#usda 1.0\n(\n    metersPerUnit = 0.01\n)\n"


def mesh(body: str, name: str = "Tri", xform: str = "") -> str:
    """A stage of one mesh prim `/name` with `body`, under an Xform with `xform` ops."""
    return HEADER + f'def Xform "Root"\n{{\n{xform}\n    def Mesh "{name}"\n    {{\n{body}\n    }}\n}}\n'


TRIANGLE = (
    "point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]\n"
    "int[] faceVertexCounts = [3]\n"
    "int[] faceVertexIndices = [0, 1, 2]\n"
)

CASES = {
    "two-vertex-face": (
        mesh(
            "point3f[] points = [(0, 0, 0), (1, 0, 0)]\nint[] faceVertexCounts = [2]\nint[] faceVertexIndices = [0, 1]"
        ),
        ["mesh /Root/Tri", "faceVertexCounts[0] is 2", "at least 3"],
    ),
    "counts-claim-more-corners": (
        mesh(TRIANGLE.replace("faceVertexCounts = [3]", "faceVertexCounts = [3, 4]")),
        ["mesh /Root/Tri", "add up to 7 corners", "has 3"],
    ),
    "huge-face-count": (
        mesh(TRIANGLE.replace("faceVertexCounts = [3]", "faceVertexCounts = [1000000000]")),
        ["mesh /Root/Tri", "add up to 1000000000 corners"],
    ),
    "index-past-points": (
        mesh(TRIANGLE.replace("[0, 1, 2]", "[0, 1, 7]")),
        ["mesh /Root/Tri", "faceVertexIndices[2] is 7", "3 points"],
    ),
    "negative-index": (
        mesh(TRIANGLE.replace("[0, 1, 2]", "[0, -1, 2]")),
        ["mesh /Root/Tri", "faceVertexIndices[1] is -1"],
    ),
    "no-points": (
        mesh("int[] faceVertexCounts = [3]\nint[] faceVertexIndices = [0, 1, 2]"),
        ["mesh /Root/Tri", "0 points"],
    ),
    "nan-point": (
        mesh(TRIANGLE.replace("(1, 0, 0)", "(nan, 0, 0)")),
        ["mesh /Root/Tri", "points[1]", "not finite"],
    ),
    "infinite-point": (
        mesh(TRIANGLE.replace("(0, 1, 0)", "(0, inf, 0)")),
        ["mesh /Root/Tri", "points[2]", "not finite"],
    ),
    "transform-overflows": (
        mesh(
            TRIANGLE,
            xform='    double3 xformOp:scale = (1e200, 1e200, 1e200)\n    uniform token[] xformOpOrder = ["xformOp:scale"]',
        ),
        ["object `Root`", "non-finite position"],
    ),
    "uvs-too-few": (
        mesh(TRIANGLE + 'texCoord2f[] primvars:st = [(0, 0), (1, 0)] (interpolation = "faceVarying")'),
        ["mesh /Root/Tri", "st has 2 values", "faceVarying", "needs 3"],
    ),
    "normals-too-few": (
        mesh(TRIANGLE + 'normal3f[] normals = [(0, 0, 1)] (interpolation = "vertex")'),
        ["mesh /Root/Tri", "normals has 1 values", "vertex"],
    ),
    "uniform-uvs-too-few": (
        mesh(
            TRIANGLE.replace("faceVertexCounts = [3]", "faceVertexCounts = [3, 3]").replace(
                "[0, 1, 2]", "[0, 1, 2, 0, 2, 1]"
            )
            + 'texCoord2f[] primvars:st = [(0, 0)] (interpolation = "uniform")'
        ),
        ["mesh /Root/Tri", "st has 1 values", "uniform", "needs 2"],
    ),
    "nan-light-intensity": (
        mesh(TRIANGLE) + 'def SphereLight "Lamp"\n{\n    float inputs:intensity = nan\n}\n',
        ["not finite"],
    ),
    "not-usd": (
        "#usda 1.0\nthis is not a stage {{{\n",
        ["cannot open the stage", "parse error"],
    ),
    "broken-reference": (
        HEADER + 'def Xform "Root" (\n    references = @./absent.usda@\n)\n{\n}\n',
        ["does not compose", "absent.usda"],
    ),
    "reference-to-missing-prim": (
        HEADER + 'def Xform "Root" (\n    references = </Nope>\n)\n{\n}\n',
        ["does not compose", "Unresolved reference prim path", "/Nope"],
    ),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_malformed_stage_is_refused_by_name_and_touches_nothing(sssbake, tmp_path, name):
    text, words = CASES[name]
    folder = tmp_path / "input"
    folder.mkdir()
    stage = folder / f"{name}.usda"
    stage.write_text(text)
    before = {p.name: p.read_bytes() for p in folder.iterdir()}
    out = tmp_path / "out"
    result = run(sssbake, "bake", str(stage), "--out", str(out), "--resolution", "16")
    assert result.returncode == 1, result.stderr
    assert str(stage) in result.stderr, result.stderr
    for word in words:
        assert word in result.stderr, f"`{word}` not in: {result.stderr}"
    assert "internal error" not in result.stderr and "Traceback" not in result.stderr
    assert not out.exists()
    assert {p.name: p.read_bytes() for p in folder.iterdir()} == before


def test_the_corpus_base_bakes_so_each_case_fails_by_what_it_breaks(sssbake, tmp_path):
    stage = tmp_path / "tri.usda"
    stage.write_text(
        mesh(TRIANGLE + 'texCoord2f[] primvars:st = [(0, 0), (1, 0), (0, 1)] (interpolation = "faceVarying")')
    )
    out = tmp_path / "out"
    result = run(sssbake, "bake", str(stage), "--out", str(out), "--resolution", "16")
    assert result.returncode == 0, result.stderr
    assert (out / "Root_subsurface.exr").is_file(), sorted(p.name for p in out.iterdir())
