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

from .cap import Cap, cap_segments, plane_edges, triangle_min_angles
from .cut import Cut, CutReport, CutWarning
from .partition import Joint, Partition, PartitionReport, Piece
from .placement import DIRECTIONS, Placement, fit_rotation, flat_faces, place_for_printing
from .plates import Plate, Plates, arrange, footprint
from .sections import (
    Section,
    layer_heights,
    section,
    section_from_distances,
    slice_layers,
)
from .split import PATTERNS, Split, classify, corner_distances, split_facets
from .stair import StairCut, StairCutError, axis_plane, stair_cut

__all__ = ["Section", "section", "slice_layers", "layer_heights", "section_from_distances", "Split", "split_facets", "classify", "corner_distances", "PATTERNS", "Cap", "plane_edges", "cap_segments", "triangle_min_angles", "Cut", "CutReport", "CutWarning", "stair_cut", "StairCut", "StairCutError", "axis_plane", "Joint", "Piece", "PartitionReport", "Partition", "fit_rotation", "Placement", "place_for_printing", "flat_faces", "DIRECTIONS", "Plate", "Plates", "arrange", "footprint"]
