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

from .._lazy import attach_stub

# The public names and their submodules are listed once, in __init__.pyi; each submodule loads
# the first time one of its names is used.
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
