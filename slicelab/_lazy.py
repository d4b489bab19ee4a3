"""Lazy re-exports for the package and its subpackages.

A subpackage lists where each public name lives; the submodule is imported
the first time the name is read, so ``import slicelab`` and the command line
do not pay for matplotlib, OpenCV or Dask until a stage needs them.
"""
from __future__ import annotations

import importlib

__all__ = ["attach"]


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
