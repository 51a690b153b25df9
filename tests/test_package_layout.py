"""The Python layout of DESIGN.md ("Growing from five chapters to fifteen"): chapters with several
algorithm families are packages, cli and demo are packages, no module imports below its first
definition, and no two modules import each other, directly or through others."""
import ast
import importlib
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "python" / "meshsmith"


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def source_modules() -> dict[str, Path]:
    return {module_name(path): path for path in sorted(PACKAGE.rglob("*.py"))}


def imported_modules(name: str, path: Path, known: set[str]) -> set[str]:
    """Every meshsmith module that `name` imports, at module level or inside a function."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level:
            base = package.split(".")
            base = base[:len(base) - node.level + 1]
            target = ".".join(base + ([node.module] if node.module else []))
            for alias in node.names:             # `from .. import geometry` imports a module
                candidate = f"{target}.{alias.name}"
                found.add(candidate if candidate in known else target)
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("meshsmith"):
            found.add(node.module)
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names if alias.name.startswith("meshsmith"))
    return {module for module in found if module in known and module != name}


def test_chapters_with_several_families_cli_and_demo_are_packages():
    for name in ("geometry", "tessellation", "decimation", "parametrization", "repair", "cli", "demo"):
        assert (PACKAGE / name / "__init__.py").is_file(), f"meshsmith.{name} should be a package"
        assert not (PACKAGE / f"{name}.py").exists(), f"meshsmith/{name}.py beside the package"


def test_no_import_below_the_first_definition():
    for name, path in source_modules().items():
        seen_definition = None
        for node in ast.parse(path.read_text()).body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef, ast.AsyncFunctionDef)):
                seen_definition = seen_definition or node.name
            elif isinstance(node, (ast.Import, ast.ImportFrom)) and seen_definition:
                pytest.fail(f"{name}: import at line {node.lineno} below the definition of {seen_definition}")


def test_no_import_cycle():
    modules = source_modules()
    graph = {name: imported_modules(name, path, set(modules)) for name, path in modules.items()}
    state: dict[str, int] = {}   # 1: on the current path, 2: done

    def visit(name: str, path: list[str]) -> None:
        state[name] = 1
        for target in sorted(graph[name]):
            if state.get(target) == 1:
                cycle = path[path.index(target):] + [target]
                pytest.fail("import cycle: " + " -> ".join(cycle))
            if target not in state:
                visit(target, path + [target])
        state[name] = 2

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])


def test_import_graph_sees_relative_imports():
    # The graph builder must find `from .b import x` / `from . import a` edges, or the test above proves nothing.
    root = PACKAGE / "decimation"
    known = set(source_modules())
    assert "meshsmith.decimation.qem" in imported_modules("meshsmith.decimation.progressive",
                                                          root / "progressive.py", known)
    assert "meshsmith.geometry" in imported_modules("meshsmith.cli.geometry", PACKAGE / "cli" / "geometry.py", known)


@pytest.mark.parametrize("chapter", ["geometry", "tessellation", "decimation", "parametrization", "repair"])
def test_public_names_are_reexported(chapter):
    module = importlib.import_module(f"meshsmith.{chapter}")
    for name in module.__all__:
        value = getattr(module, name)
        owner = getattr(value, "__module__", None)
        if owner is not None and callable(value):
            assert owner.startswith(f"meshsmith.{chapter}"), f"{chapter}.{name} comes from {owner}"
