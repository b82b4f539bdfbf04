"""Every bake setting is defined once, in the library (rust/io/src/settings.rs), and every
door reads it from there: the command line's flags, the Python keywords and their typed
stubs (python/sssbake/options.py), the docs' table (docs/pipelines.md), the Blender add-on's
properties. The generated files are checked here against the library; with
SSSBAKE_UPDATE_DOCS=1 this test rewrites them instead."""

import os
import re
import subprocess

import pytest
from conftest import ROOT, run

OPTIONS_FILE = ROOT / "python" / "sssbake" / "options.py"
PIPELINES = ROOT / "docs" / "pipelines.md"
BEGIN = "<!-- BEGIN settings table: generated; SSSBAKE_UPDATE_DOCS=1 pytest tests/test_settings.py -->"
END = "<!-- END settings table -->"


@pytest.fixture(scope="module")
def settings():
    import sssbake

    return sssbake.settings()


def range_text(setting: dict) -> str:
    """A setting's range and unit in words, or ''."""
    unit = f" {setting['unit']}" if setting["unit"] else ""
    kind = setting["kind"]
    if kind == "count":
        most = "" if setting["max"] >= 2**32 - 1 else f" to {setting['max']}"
        return f"{setting['min']}{most}{unit}" if most else f"at least {setting['min']}{unit}"
    if kind == "number":
        low, high = setting["min"], setting["max"]
        if low is not None and high is not None:
            return f"{low:g} to {high:g}{unit}"
        if low is not None:
            return f"{'above' if setting['min_exclusive'] else 'at least'} {low:g}{unit}"
        return unit.strip()
    if kind == "size":
        return "a size such as 16G or 512M"
    return ""


def python_type(setting: dict) -> str:
    names = ", ".join(f'"{n}"' for n in setting.get("names", []))
    return {
        "count": "int",
        "number": "float",
        "switch": "bool",
        "choice": f"Literal[{names}]",
        "choices": f"Sequence[Literal[{names}]]",
        "names": "Sequence[str]",
        "file": "str | os.PathLike[str]",
        "size": "str",
    }[setting["kind"]]


def options_module(settings: list[dict]) -> str:
    lines = [
        '"""The options `sssbake.bake`, `plan` and `batch` take as keywords, and a batch',
        "manifest's tables: every setting of the library (`sssbake.settings()`), typed.",
        "",
        "Generated from the library by tests/test_settings.py (SSSBAKE_UPDATE_DOCS=1); do not edit.",
        '"""',
        "",
        "from __future__ import annotations",
        "",
        "import os",
        "from collections.abc import Sequence",
        "from typing import Literal, TypedDict",
        "",
        "",
        "class Options(TypedDict, total=False):",
        '    """Each option left out keeps the library\'s default."""',
        "",
    ]
    for s in settings:
        detail = "; ".join(part for part in (range_text(s), f"default: {s['default_text']}") if part)
        lines.append(f"    {s['name']}: {python_type(s)}")
        lines.append(f'    """{s["doc"].rstrip(".")} ({detail})."""')
    return formatted("\n".join(lines) + "\n")


def formatted(source: str) -> str:
    """`source` as ruff formats it (the repository's style), so the file passes the lint."""
    ruff = ROOT / ".venv" / "bin" / "ruff"
    result = subprocess.run(
        [str(ruff), "format", "--stdin-filename", str(OPTIONS_FILE), "-"],
        input=source,
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
    )
    return result.stdout


def docs_table(settings: list[dict]) -> str:
    rows = ["| option | what it sets | takes | default |", "|---|---|---|---|"]
    for s in settings:
        takes = range_text(s) or {
            "choice": " / ".join(f"`{n}`" for n in s.get("names", [])),
            "choices": "a list of " + ", ".join(f"`{n}`" for n in s.get("names", [])),
            "names": "a list of names",
            "file": "a file",
            "switch": "`true` / `false`",
        }.get(s["kind"], "")
        if s["kind"] == "choice" and len(s.get("names", [])) > 10:
            takes = "a name (`sssbake presets`)"
        part = s["part"] if isinstance(s["part"], str) else f"{s['part']['integrator']} only"
        doc = s["doc"] if part in ("scene", "bake", "writing") else s["doc"].split(": ", 1)[-1]
        prefix = "" if part in ("scene", "bake", "writing") else f"*{part.split()[0]}*: "
        rows.append(f"| `{s['name']}` | {prefix}{doc} | {takes} | {s['default_text']} |")
    return "\n".join(rows)


def check_or_update(path, want: str):
    if os.environ.get("SSSBAKE_UPDATE_DOCS"):
        path.write_text(want)
    assert path.read_text() == want, (
        f"{path.relative_to(ROOT)} is not the library's settings; rewrite it with\n"
        "    SSSBAKE_UPDATE_DOCS=1 .venv/bin/python -m pytest tests/test_settings.py"
    )


def test_the_python_options_are_the_librarys(settings):
    check_or_update(OPTIONS_FILE, options_module(settings))


def test_the_docs_table_is_the_librarys(settings):
    text = PIPELINES.read_text()
    before, rest = text.split(BEGIN, 1)
    _, after = rest.split(END, 1)
    check_or_update(PIPELINES, f"{before}{BEGIN}\n\n{docs_table(settings)}\n\n{END}{after}")


def test_every_setting_states_what_it_is(settings):
    names = [s["name"] for s in settings]
    assert len(names) == len(set(names)) > 25
    for s in settings:
        assert s["doc"] and s["default_text"], s
        if s["default"] is not None and s["kind"] in ("count", "number"):
            low, high = s["min"], s["max"]
            assert (low is None or s["default"] >= low) and (high is None or s["default"] <= high), s


def test_the_command_line_has_a_flag_for_every_setting(sssbake, settings):
    """`sssbake bake --help` lists every setting as its flag, with the library's default."""
    result = run(sssbake, "bake", "--help")
    assert result.returncode == 0, result.stderr
    for s in settings:
        flag = "--object" if s["name"] == "objects" else "--" + s["name"].replace("_", "-")
        assert re.search(rf"^\s+{flag}\b", result.stdout, re.MULTILINE), flag
        if s["kind"] != "switch":
            assert f"[default: {s['default_text']}" in result.stdout, s["name"]


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("resolution", 0),
        ("colour_split", 1.5),
        ("tolerance", 0.0),
        ("light_check", 70000),
        ("method", "fast"),
    ],
)
def test_one_range_refuses_a_value_at_every_door(sssbake, field, value):
    """The command line and the Python keywords refuse the same value by the same check."""
    import sssbake as package

    flag = "--" + field.replace("_", "-")
    result = run(sssbake, "plan", str(ROOT / "examples" / "marble" / "marble.gltf"), flag, str(value))
    assert result.returncode != 0
    with pytest.raises(package.SettingError) as error:
        package.plan(str(ROOT / "examples" / "marble" / "marble.gltf"), **{field: value})
    assert error.value.field == field
    # The same words at both doors (clap words a wrong name itself).
    if field != "method":
        words = error.value.message.removeprefix(f"{field}: ")
        assert words in result.stderr, (words, result.stderr)
    assert f"'{value}'" in result.stderr
