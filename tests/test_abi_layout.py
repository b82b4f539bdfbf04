"""The add-on's ctypes structures lay out as the header's: a C program, generated from the
fields sssbake.h declares and compiled with cc, prints each structure's size and every
field's offset, and they must equal the ctypes Structure's, field for field and by name,
so a field added to one side only fails."""

import json
import re
import subprocess
import sys

import pytest
from conftest import ROOT

HEADER = ROOT / "rust" / "ffi" / "include" / "sssbake.h"
# C structure: the add-on's ctypes class of the same layout.
STRUCTURES = {
    "SssbakeMesh": "Mesh",
    "SssbakeLight": "Light",
    "SssbakeMaterial": "Material",
    "SssbakeSettings": "Settings",
}


def header_fields(text, struct):
    """The field names `struct` declares in the header, in order."""
    name = re.escape(struct)
    body = re.search(rf"typedef struct {name} \{{(.*?)\}} {name};", text, re.DOTALL)
    assert body, f"{struct} is not in {HEADER}"
    code = re.sub(r"/\*.*?\*/", "", body.group(1), flags=re.DOTALL)
    declarations = [d.strip() for d in code.split(";") if d.strip()]
    return [re.search(r"(\w+)\s*(\[[^\]]*\])?$", d).group(1) for d in declarations]


@pytest.fixture(scope="module")
def c_layout(tmp_path_factory):
    """{struct: {"size": n, "fields": [[name, offset, size], ...]}} as the C compiler lays them out."""
    text = HEADER.read_text()
    lines = [
        "#include <stddef.h>",
        "#include <stdio.h>",
        '#include "sssbake.h"',
        "int main(void) {",
        'printf("{");',
    ]
    for i, struct in enumerate(STRUCTURES):
        fields = header_fields(text, struct)
        lines.append(
            f'printf("%s\\"{struct}\\": {{\\"size\\": %zu, \\"fields\\": [", "{", " if i else ""}", sizeof({struct}));'
        )
        for j, field in enumerate(fields):
            lines.append(
                f'printf("%s[\\"{field}\\", %zu, %zu]", "{", " if j else ""}", '
                f"offsetof({struct}, {field}), sizeof((({struct} *)0)->{field}));"
            )
        lines.append('printf("]}");')
    lines += ['printf("}\\n");', "return 0;", "}"]
    work = tmp_path_factory.mktemp("layout")
    source, program = work / "layout.c", work / "layout"
    source.write_text("\n".join(lines) + "\n")
    subprocess.run(
        ["cc", "-std=c99", "-Wall", "-Werror", "-I", str(HEADER.parent), str(source), "-o", str(program)],
        check=True,
    )
    return json.loads(subprocess.run([str(program)], check=True, capture_output=True, text=True).stdout)


@pytest.fixture(scope="module")
def native():
    # The structures need no library: native imports without loading it.
    sys.path.insert(0, str(ROOT / "blender_addon" / "sssbake"))
    try:
        import native as module
    finally:
        sys.path.pop(0)
    return module


@pytest.mark.parametrize("struct", STRUCTURES)
def test_the_ctypes_structures_match_the_header(c_layout, native, struct):
    import ctypes

    cls = getattr(native, STRUCTURES[struct])
    ours = [[name, getattr(cls, name).offset, getattr(cls, name).size] for name, _ in cls._fields_]
    assert ours == c_layout[struct]["fields"], struct
    assert ctypes.sizeof(cls) == c_layout[struct]["size"], struct


def test_the_header_parser_reads_every_field():
    # A declaration the parser missed would go unchecked; SssbakeLight has seventeen.
    fields = header_fields(HEADER.read_text(), "SssbakeLight")
    assert fields[:2] == ["kind", "colour"] and len(fields) == 17, fields


def test_the_add_ons_numbers_are_the_headers(native):
    # A kind, method or extension the add-on numbers differently would bake the wrong thing
    # with no error; every number it sends is checked against the header's #define.
    defines = {
        name: int(value) for name, value in re.findall(r"#define SSSBAKE_(\w+) (\d+)", HEADER.read_text())
    }
    ours = {"ABI_VERSION": native.ABI_VERSION}
    for kind in ("SUN", "POINT", "SPOT", "RECTANGLE", "DISK"):
        ours[f"LIGHT_{kind}"] = getattr(native, f"LIGHT_{kind}")
    for kind in ("PRESET", "PRINCIPLED", "TOML", "SCENE", "SIDECAR", "NONE"):
        ours[f"MATERIAL_{kind}"] = getattr(native, f"MATERIAL_{kind}")
    for blender, number in native.SUBSURFACE_METHODS.items():
        ours[f"SUBSURFACE_{blender}"] = number
    for blender, number in native.EXTENSIONS.items():
        ours[f"EXTENSION_{blender}"] = number
    ours["ALBEDO_CYCLES"], ours["ALBEDO_PHYSICAL"] = native.ALBEDO_CYCLES, native.ALBEDO_PHYSICAL
    assert ours == {name: defines.get(name) for name in ours}
