"""The bake core's modules import each other in no circle longer than two files: a
module reads the ones below it (the layout, the prepared object, the scattering) and
not the ones that orchestrate it, so each can be read and changed on its own."""

import re

from conftest import ROOT

BAKE = ROOT / "rust" / "bake" / "src"


def module_imports() -> dict[str, set[str]]:
    """Each module of rust/bake/src (a path such as `transport::octree`) and the modules
    its code names through `crate::` or `super::` (comments left out)."""
    modules = {}
    for path in BAKE.rglob("*.rs"):
        parts = list(path.relative_to(BAKE).with_suffix("").parts)
        if parts[-1] == "mod":
            parts = parts[:-1]
        if parts != ["lib"]:
            modules["::".join(parts)] = path
    imports = {}
    for name, path in modules.items():
        code = "\n".join(line for line in path.read_text().splitlines() if not line.strip().startswith("//"))
        parent = name.split("::")[:-1]
        named = re.findall(r"crate::([a-z_][a-z0-9_:]*)", code)
        named += ["::".join([*parent, n]) for n in re.findall(r"super::([a-z_][a-z0-9_]*)", code)]
        for group in re.findall(r"crate::\{([^}]*)\}", code):
            named += [item.strip() for item in group.split(",")]
        found = set()
        for reference in named:
            parts = reference.split("::")
            for k in range(len(parts), 0, -1):
                candidate = "::".join(parts[:k])
                if candidate in modules:
                    found.add(candidate)
                    break
        imports[name] = found - {name}
    return imports


def longest_circle(imports: dict[str, set[str]]) -> list[str]:
    """The longest simple circle of imports (each found once, from its first module)."""
    best: list[str] = []

    def walk(start: str, node: str, path: list[str]):
        nonlocal best
        for following in sorted(imports[node]):
            if following == start and len(path) > len(best):
                best = list(path)
            elif following > start and following not in path:
                walk(start, following, [*path, following])

    for module in sorted(imports):
        walk(module, module, [module])
    return best


def test_the_finder_sees_a_circle():
    assert longest_circle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == ["a", "b", "c"]


def test_no_import_circle_in_the_bake_core_is_longer_than_two_files():
    imports = module_imports()
    assert len(imports) > 50 and imports["pipeline"] >= {"prepared", "layout", "request"}
    circle = longest_circle(imports)
    assert len(circle) <= 2, " → ".join([*circle, circle[0]])
