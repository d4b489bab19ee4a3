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
    """Imports form no cycle between modules, at any level: an import deferred into a function is
    a dependency all the same."""
    modules = _modules()
    graph: dict[str, set[str]] = {m: set() for m in modules}
    for importer, target, _, subs in _imports(top_level_only=False):
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


# Floors of the package, lowest first: a subpackage imports only from floors below its own, at
# any level (a deferred import inside a function counts: it is a dependency all the same). The
# private helpers at the root (`_lazy`, `_pools`) are the basement and import nothing of slicelab.
FLOORS = [["_lazy", "_pools"], ["geometry"], ["files"], ["mesh"], ["samples", "slicing"],
          ["printing", "artefacts"], ["gcode"], ["viz"], ["tasks"], ["cli"], ["__main__"]]


def _floor(module: str) -> tuple[str, int]:
    parts = module.split(".")
    name = parts[1] if len(parts) > 1 else ""
    for level, names in enumerate(FLOORS):
        if name in names:
            return name, level
    return name, len(FLOORS)      # the package's __init__: the top, it re-exports every floor


def test_every_subpackage_is_on_a_floor():
    subs = {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    subs |= {p.stem for p in PACKAGE.glob("_*.py") if p.stem != "__init__"} | {"__main__"}
    assert subs == {n for names in FLOORS for n in names}


def test_no_import_goes_up_a_floor():
    """Ground floors (geometry, files, mesh) import nothing above them; no two subpackages import each other."""
    bad = []
    for importer, target, names, _ in _imports(top_level_only=False):
        (a, fa), (b, fb) = _floor(importer), _floor(target)
        if target == "slicelab" and names == ["__version__"]:
            continue      # the version string, set before anything else is imported
        if a != b and fb >= fa:
            bad.append(f"{importer} (floor {fa}) imports {target} (floor {fb})")
    assert not bad, "\n".join(bad)


MAX_FUNCTION_LINES = 120
MAX_POSITIONAL = 8


def _compiled(node: ast.FunctionDef) -> bool:
    """A numba kernel: plain arrays in, plain arrays out (it cannot take a dataclass)."""
    return any("jit" in ast.unparse(d) for d in node.decorator_list)


def test_functions_are_short_and_take_few_positional_arguments():
    """A function does one thing (at most 120 lines past its docstring) and takes its data in few
    positional arguments (at most 8; options are keyword-only): more is a stage that wants a
    dataclass. Compiled kernels take plain arrays and are exempt."""
    bad = []
    for module, path in _modules().items():
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) or _compiled(node):
                continue
            body = node.body
            doc = body[0] if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                and isinstance(body[0].value.value, str) else None
            lines = node.end_lineno - node.lineno + 1 - (doc.end_lineno - doc.lineno + 1 if doc else 0)
            positional = [a.arg for a in node.args.posonlyargs + node.args.args if a.arg not in ("self", "cls")]
            if lines > MAX_FUNCTION_LINES or len(positional) > MAX_POSITIONAL:
                bad.append(f"{module}.{node.name}: {lines} lines, {len(positional)} positional arguments")
    assert not bad, "\n".join(bad)
