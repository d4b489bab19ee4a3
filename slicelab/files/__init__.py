"""Files: written whole or not at all, numbers as text, the one SVG writer.

A ground floor: it imports nothing of slicelab but `slicelab.geometry.compiled`
(the compiled number formatter).

==========================  =====================================================
``files.atomic``            `atomic_path`, `atomic_open`, `same_file`, `StagedFolder`: no half-written file
``files.numbers``           `put_number`, `path_data`: numbers written by compiled loops, as Python writes them
``files.svg``               `SvgDrawing`: the one SVG writer of every drawing
==========================  =====================================================

See Also
--------
slicelab.mesh.written : STL whose report is the check of the file read back.
slicelab.gcode : G-code, written with `files.numbers`.
"""
from __future__ import annotations

from .._lazy import attach_stub

# The public names and their submodules are listed once, in __init__.pyi; each submodule loads
# the first time one of its names is used.
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
