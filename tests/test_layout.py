"""The package's shape: public API, no private imports across modules, no cycles, small modules."""
from __future__ import annotations

import ast
import importlib
import subprocess
import sys
import types
from pathlib import Path

import pytest

import slicelab

PACKAGE = Path(slicelab.__file__).parent
SUBPACKAGES = ["geometry", "mesh", "slicing", "printing", "gcode", "artefacts", "files", "viz", "tasks"]
MAX_LINES = 600


def _modules() -> dict[str, Path]:
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _resolve(module: str, path: Path, node: ast.ImportFrom) -> str | None:
    """Absolute name of the module an ImportFrom reads from (None outside slicelab)."""
    if node.level == 0:
        return node.module if node.module and node.module.split(".")[0] == "slicelab" else None
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    base = package.split(".")
    if node.level > 1:
        base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports(top_level_only: bool):
    """(importer, imported module, names, node) for every `from ... import` inside slicelab."""
    modules = _modules()
    for module, path in modules.items():
        tree = ast.parse(path.read_text())
        nodes = tree.body if top_level_only else ast.walk(tree)
        for node in nodes:
            if isinstance(node, ast.ImportFrom):
                target = _resolve(module, path, node)
                if target is None:
                    continue
                names = [a.name for a in node.names]
                # `from . import x` may name a submodule.
                subs = [f"{target}.{n}" for n in names if f"{target}.{n}" in modules]
                yield module, target, names, subs


def test_every_top_level_name_imports():
    for name in slicelab.__all__:
        assert getattr(slicelab, name) is not None, name
    for name in ("split", "cut", "partition", "plan", "section", "check", "align", "profile"):
        assert callable(getattr(slicelab, name)) and not isinstance(getattr(slicelab, name), types.ModuleType)


@pytest.mark.parametrize("sub", SUBPACKAGES)
def test_each_subpackage_exports_its_all(sub):
    package = importlib.import_module(f"slicelab.{sub}")
    assert package.__all__, sub
    assert len(set(package.__all__)) == len(package.__all__)
    for name in package.__all__:
        assert hasattr(package, name), f"slicelab.{sub}.{name}"
    assert package.__doc__ and all(f"``{sub}." in package.__doc__ for _ in [0])


def test_the_package_docstring_lists_every_subpackage():
    for sub in SUBPACKAGES:
        assert f"``slicelab.{sub}``" in slicelab.__doc__


def test_a_module_named_like_its_function_is_a_module():
    code = ("import types, slicelab.slicing.split as m, slicelab.slicing.cut as c, slicelab\n"
            "assert isinstance(m, types.ModuleType) and isinstance(c, types.ModuleType)\n"
            "assert callable(slicelab.split) and slicelab.split is m.split and slicelab.cut is c.cut\n"
            "print(type(m).__name__)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "module"


def test_no_private_name_is_imported_across_modules():
    bad = [f"{importer} imports {name} from {target}"
           for importer, target, names, _ in _imports(top_level_only=False)
           for name in names if name.startswith("_") and name != "__version__"]
    assert not bad, "\n".join(bad)


def test_no_test_imports_a_private_name():
    bad = []
    for path in sorted(Path(__file__).parent.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("slicelab"):
                bad += [f"{path.name}: {a.name} from {node.module}" for a in node.names
                        if a.name.startswith("_")]
    assert not bad, "\n".join(bad)


def test_no_import_cycle_between_modules():
    """Module-level imports form no cycle (imports inside functions are deferred by design)."""
    modules = _modules()
    graph: dict[str, set[str]] = {m: set() for m in modules}
    for importer, target, _, subs in _imports(top_level_only=True):
        for t in [target, *subs]:
            if t in modules and t != importer and not importer.startswith(t + "."):
                graph[importer].add(t)
    # A package's __init__ importing its own submodules is how re-exports work; a submodule
    # importing its package's __init__ (``from .. import x``) is the cycle to catch.
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(m):
        state[m] = 1
        stack.append(m)
        for n in sorted(graph[m]):
            if state.get(n) == 1:
                cycle = stack[stack.index(n):] + [n]
                pytest.fail("import cycle: " + " -> ".join(cycle))
            if n not in state:
                visit(n)
        stack.pop()
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m)


def test_no_module_is_over_600_lines():
    long = {m: n for m, p in _modules().items() if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert not long, long
