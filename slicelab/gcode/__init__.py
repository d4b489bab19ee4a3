"""G-code: a print plan written for a printer, its time estimated, its layers drawn.

==========================  =====================================================
``gcode.writer``            `write_gcode`, `gcode_lines`: the header, the layers, the end
``gcode.layer_inputs``      a layer's arrays and the settings' numbers for the compiled pass
``gcode.text_kernels``      the compiled pass: a layer's G-code text, filament and time
``gcode.estimate``          print time of the moves (trapezoids, look-ahead)
``gcode.layer_svgs``        per-layer SVG drawings of a print plan
==========================  =====================================================
"""
from __future__ import annotations

from .._lazy import attach

# Submodule of each public name: they load on first use.
_WHERE = {"write_gcode": "writer", "gcode_lines": "writer", "header_value": "writer", "layer_fan": "writer",
          "layer_texts": "writer", "write_svgs": "layer_svgs", "layer_drawings": "layer_svgs",
          "svg_page": "layer_svgs", "move_times": "estimate", "format_duration": "estimate"}

__all__ = list(_WHERE)

__getattr__, __dir__ = attach(__name__, _WHERE, globals())
