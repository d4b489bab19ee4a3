"""Docstrings of re-exported constants: their own ``#:`` comment, never their type's docstring.

A constant such as ``slicelab.printing.PATTERNS`` (a dict) or
``slicelab.geometry.GUO_HALL`` (a numpy array) has no docstring of its own:
autodoc would show its type's (``dict``'s, ``ndarray``'s) as if it were the
constant's. And its ``#:`` comment is in the module that defines it, while
autodoc looks in the subpackage that re-exports it. This handler of
``autodoc-process-docstring`` puts in its place the ``#:`` comment found by following the subpackage's ``from .module
import NAME`` lines (in ``__init__.pyi`` for a lazily loaded subpackage, else in
``__init__.py``) to the module that assigns the name, or drops the docstring
when the constant has none of its own.
"""
from __future__ import annotations

import ast
import importlib.util
from pathlib import Path


def _source(module: str) -> tuple[Path, bool] | None:
    """The file that lists `module`'s names (its stub if it has one) and whether it is a package."""
    spec = importlib.util.find_spec(module)
    if spec is None or not spec.origin or not spec.origin.endswith(".py"):
        return None
    path = Path(spec.origin)
    stub = path.with_suffix(".pyi")
    return (stub if stub.exists() else path), path.name == "__init__.py"


def defining_comment(module: str, name: str, depth: int = 0) -> list[str]:
    """The ``#:`` comment lines of `name` where it is assigned, following re-exports from `module`."""
    from sphinx.pycode import ModuleAnalyzer

    if depth > 5:
        return []
    try:
        docs = ModuleAnalyzer.for_module(module).find_attr_docs()
    except Exception:
        docs = {}
    if ("", name) in docs:
        return list(docs[("", name)])
    found = _source(module)
    if found is None:
        return []
    path, is_package = found
    package = module if is_package else module.rsplit(".", 1)[0]
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.ImportFrom) and node.level >= 1:
            for alias in node.names:
                if (alias.asname or alias.name) == name:
                    base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                    target = ".".join(base + ([node.module] if node.module else []))
                    return defining_comment(target, alias.name, depth + 1)
    return []


def process_docstring(app, what, name, obj, options, lines):
    if what != "data" or "." not in name:
        return
    module, attr = name.rsplit(".", 1)
    comment = defining_comment(module, attr)
    if comment:
        lines[:] = [*comment, ""]
    elif "__doc__" not in getattr(obj, "__dict__", {}):
        lines[:] = []          # the docstring of its type (dict's, ndarray's), not its own


def setup(app):
    # Before numpydoc (priority 500), which would otherwise render the type's docstring.
    app.connect("autodoc-process-docstring", process_docstring, priority=100)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
