"""Writing results: safe files, checked meshes, drawings, G-code.

==========================  =====================================================
``export.files``            `atomic_path`, `atomic_open`: no half-written file
``export.meshes``           `write_mesh`: STL whose report is the check of the file
``export.svg``              `SvgDrawing`: the one SVG writer of every drawing
``export.gcode``            G-code and per-layer SVGs of a print plan
==========================  =====================================================
"""
from __future__ import annotations

import importlib

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"WrittenMesh": "meshes", "write_mesh": "meshes", "as_float32": "meshes", "SvgDrawing": "svg", "atomic_path": "files", "atomic_open": "files", "write_gcode": "gcode", "gcode_lines": "gcode", "write_svgs": "gcode"}


__all__ = ["WrittenMesh", "write_mesh", "as_float32", "SvgDrawing", "atomic_path", "atomic_open", "write_gcode", "gcode_lines", "write_svgs"]


def __getattr__(name):
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
