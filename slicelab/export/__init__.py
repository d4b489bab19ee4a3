"""Writing results: safe files, checked meshes, the one SVG writer.

==========================  =====================================================
``export.files``            `atomic_path`, `atomic_open`: no half-written file
``export.meshes``           `write_mesh`: STL whose report is the check of the file
``export.svg``              `SvgDrawing`: the one SVG writer of every drawing
``export.profile_files``     a vessel's profile as DXF (CAD) and CSV (GIS, spreadsheets)
==========================  =====================================================
"""
from __future__ import annotations

from .._lazy import attach

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"WrittenMesh": "meshes", "write_mesh": "meshes", "as_float32": "meshes", "SvgDrawing": "svg", "atomic_path": "files", "atomic_open": "files"}


__all__ = ["WrittenMesh", "write_mesh", "as_float32", "SvgDrawing", "atomic_path", "atomic_open"]


__getattr__, __dir__ = attach(__name__, _WHERE, globals())
