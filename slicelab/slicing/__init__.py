"""Slicing a mesh by planes: sections, splits, watertight cuts and partitions.

==========================  =====================================================
``slicing.sections``        `section`, `slice_layers` -> `Section`
``slicing.split``           `split` -> `Split` (front, rear, section), facet patterns
``slicing.cap``             `Cap`, `plane_edges`, `cap_segments`: constrained Delaunay caps
``slicing.cut``             `cut` -> `Cut`: two closed parts, each capped on the plane
``slicing.stair``           `stair_cut` -> `StairCut`: an interlocking stair joint
``slicing.partition``       `partition` -> `Partition`: printable pieces, flat or stair joints
``slicing.placement``       each piece laid on a flat face, turned to fit, centred on the bed
``slicing.plates``          `arrange` pieces onto as few build plates as they fit
==========================  =====================================================

The functions named like their module (`split`, `cut`, `partition`) are
reached as ``slicelab.split`` (or ``slicelab.slicing.split.split``):
``slicelab.slicing.split`` is the module.
"""
from __future__ import annotations

from .._lazy import attach_stub

# The public names and their submodules are listed once, in __init__.pyi; each submodule loads
# the first time one of its names is used.
_SUBMODULES = ('sections', 'split', 'cap', 'cut', 'stair', 'partition', 'placement', 'plates')

__getattr__, __dir__, __all__ = attach_stub(__name__, __file__, submodules=_SUBMODULES)
