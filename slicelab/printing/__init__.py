"""The printing half: layer rasters, distance fields, perimeters, infill, paths and the print plan.

==========================  =====================================================
``printing.planner``        `plan` a whole part -> `PrintPlan`
``printing.table``          `LayerPaths`: a layer's toolpaths as a table, a row per path
``printing.roles``          path kinds and roles, their G-code ``;TYPE:`` words and colours
``printing.grid``           a layer on the pixel grid: masks, rasters, hole hierarchy, distance fields
``printing.steps``          perimeters, gap fill, skins, overhangs and bridges, skirt, paths, simplification
``printing.fill``           filling lines and the infill patterns by name
``printing.supports``       support material under unheld overhangs and mid-air islands
``printing.config``         `PrintSettings` in groups, printer profiles and settings files, the bed
``printing._reuse``         layers that repeat, planned once (private)
``printing._schedule``      which runs of layers the workers take first (private)
==========================  =====================================================
"""
from __future__ import annotations

from .._lazy import attach_stub

# The public names and their submodules are listed once, in __init__.pyi; each submodule loads
# the first time one of its names is used.
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
