"""Writing results: safe files, checked meshes, drawings, G-code.

==========================  =====================================================
``export.files``            `atomic_path`, `atomic_open`: no half-written file
``export.meshes``           `write_mesh`: STL whose report is the check of the file
``export.svg``              `SvgDrawing`: the one SVG writer of every drawing
``export.gcode``            G-code of a print plan
``export.layer_svgs``       per-layer SVG drawings of a print plan
``export.layer_inputs``     a layer's arrays and the settings' numbers for the compiled G-code pass
``export.text_kernels``     the compiled pass: a layer's G-code text, filament and time
==========================  =====================================================
"""
from __future__ import annotations

from .._lazy import attach

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"WrittenMesh": "meshes", "write_mesh": "meshes", "as_float32": "meshes", "SvgDrawing": "svg", "atomic_path": "files", "atomic_open": "files", "write_gcode": "gcode", "gcode_lines": "gcode", "write_svgs": "layer_svgs", "layer_fan": "gcode", "layer_texts": "gcode", "layer_drawings": "layer_svgs", "svg_page": "layer_svgs"}


__all__ = ["WrittenMesh", "write_mesh", "as_float32", "SvgDrawing", "atomic_path", "atomic_open", "write_gcode", "gcode_lines", "write_svgs", "layer_fan", "layer_texts", "layer_drawings", "svg_page"]


__getattr__, __dir__ = attach(__name__, _WHERE, globals())
