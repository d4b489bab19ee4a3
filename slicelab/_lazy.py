"""Lazy re-exports for the package and its subpackages.

A subpackage lists where each public name lives; the submodule is imported
the first time the name is read, so ``import slicelab`` and the command line
do not pay for matplotlib, OpenCV or Dask until a stage needs them. The list
is the subpackage's type stub, ``__init__.pyi`` (`attach_stub`), as in
scikit-image: static tools and IDEs read the same file.

References
----------
.. [1] Scientific Python, "SPEC 1 - Lazy Loading of Submodules and Functions",
   https://scientific-python.org/specs/spec-0001/
"""
from __future__ import annotations

import ast
import importlib
from pathlib import Path

__all__ = ["attach", "attach_stub", "stub_names"]


def attach(package: str, where: dict[str, str], eager: dict | None = None, submodules=()):
    """Module ``__getattr__`` and ``__dir__`` for `package`, resolving `where` (name -> submodule)
    and the `submodules` themselves (``slicelab.samples`` without importing it first).

    Examples
    --------
    >>> getattr_, dir_ = attach("slicelab.geometry", {"Frame": "planes"})
    >>> getattr_("Frame").__name__
    'Frame'
    """
    namespace = eager if eager is not None else {}

    def __getattr__(name):
        if name in submodules:
            value = importlib.import_module(f".{name}", package)
            namespace[name] = value
            return value
        module = where.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f".{module}", package), name)
        namespace[name] = value
        return value

    def __dir__():
        return sorted(set(namespace) | set(where) | set(submodules))

    return __getattr__, __dir__


def stub_names(stub) -> dict[str, str]:
    """Name -> submodule, from the ``from .module import name as name`` lines of a type stub.

    Examples
    --------
    >>> import slicelab.gcode, pathlib
    >>> stub_names(pathlib.Path(slicelab.gcode.__file__).with_suffix(".pyi"))["write_gcode"]
    'writer'
    """
    where = {}
    for node in ast.parse(Path(stub).read_text()).body:
        if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module:
            where.update({a.asname or a.name: node.module for a in node.names})
    return where


def attach_stub(package: str, file: str, submodules=()):
    """`attach` with the names listed in the package's ``__init__.pyi``, next to `file`; also
    returns ``__all__``, the names in the stub's order.

    See Also
    --------
    attach : the same from a dict.
    """
    import sys
    where = stub_names(Path(file).with_suffix(".pyi"))
    # (the package's own namespace: a name, once loaded, is found there without a call)
    getattr_, dir_ = attach(package, where, vars(sys.modules[package]), submodules)
    return getattr_, dir_, list(where)
