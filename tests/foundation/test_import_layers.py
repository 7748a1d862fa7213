"""The package's layering, read from the source: no module imports a layer above its own, and no
runtime import cycle exists between modules (imports under `if TYPE_CHECKING:` do not run)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "src" / "eigengait"

# Lower number = lower layer; a module may import its own top-level part or strictly lower ones.
LAYERS = {
    "errors": 0,
    "inputs": 1,
    "outputs": 1,
    "geometry": 1,
    "body_tree": 1,
    "json_text": 1,
    "figures": 1,
    "files": 2,
    "character": 3,
    "cloth": 3,
    "sim": 4,
    "modal": 5,
    "control": 6,
    "optimize": 7,
    "motion": 7,
    "render": 8,
    "studio": 9,
    "cli": 10,
    "__main__": 11,
}


def _module_name(path: Path) -> str:
    parts = ("eigengait", *path.relative_to(PACKAGE).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _runtime_imports(path: Path) -> set[str]:
    """Modules of the package imported when `path` runs (TYPE_CHECKING blocks skipped); `from P
    import name` counts as importing P.name when that is a module of the package."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skipped = {
        id(inner)
        for node in ast.walk(tree)
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)
        for inner in ast.walk(node)
    }
    found = set()
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name.startswith("eigengait")}
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("eigengait"):
            for alias in node.names:
                sub = f"{node.module}.{alias.name}"
                found.add(sub if _is_module(sub) else node.module)
    return found


def _is_module(name: str) -> bool:
    rel = Path(*name.split(".")[1:])
    return (PACKAGE / rel).with_suffix(".py").exists() or (PACKAGE / rel / "__init__.py").exists()


def _part(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


GRAPH = {_module_name(p): _runtime_imports(p) for p in sorted(PACKAGE.rglob("*.py"))}


def test_every_top_level_part_has_a_layer():
    assert {_part(m) for m in GRAPH} - {""} == set(LAYERS)


@pytest.mark.parametrize("module", sorted(GRAPH))
def test_no_upward_import(module):
    upward = [
        target
        for target in GRAPH[module]
        if _part(target)
        and _part(target) != _part(module)
        and LAYERS[_part(target)] >= LAYERS[_part(module)]
    ]
    assert not upward, f"{module} imports {upward} from its own layer or above"


def test_no_runtime_import_cycle():
    state: dict[str, int] = {}
    cycles = []

    def visit(module: str, path: list[str]) -> None:
        state[module] = 1
        for target in sorted(GRAPH.get(module, ())):
            # a package's own __init__ importing its submodules is not a cycle through them
            if module.startswith(target + "."):
                continue
            if state.get(target) == 1:
                cycles.append([*path[path.index(target) :], target])
            elif target not in state:
                visit(target, [*path, target])
        state[module] = 2

    for module in GRAPH:
        if module not in state:
            visit(module, [module])
    assert not cycles, f"import cycles: {cycles}"
