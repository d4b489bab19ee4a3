"""Figures and previews (matplotlib, imported on first use).

==========================  =====================================================
``viz.layers``              rasters, distance fields, toolpaths, coverage, 3-D plan, PNG preview
``viz.layer_choice``        which layers a preview draws (``--preview-layers``)
``viz.depth``               depth-buffer drawing of millions of facets, decimated
``viz.canvas``              figures composed as pixel arrays (OpenCV), PNG
``viz.preview``             depth-rendered split previews
``viz.partition``           exploded views of cut or partitioned pieces
``viz.plates``              top views of build plates, pieces numbered
``viz.profile``             the archaeological profile drawing as a PNG
``viz.rims``                a batch's rim-diameter chart, weighted by rim EVE
==========================  =====================================================
"""
from __future__ import annotations

from .._lazy import attach_stub

# The public names and their submodules are listed once, in __init__.pyi; each submodule loads
# the first time one of its names is used.
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
