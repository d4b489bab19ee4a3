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

from .._lazy import attach

# Submodule of each public name: they load on first use, so slicing layers (`slice_layers`)
# does not load the cuts, partitions and plates.
_WHERE = {"Section": "sections", "section": "sections", "slice_layers": "sections", "layer_heights": "sections",
          "section_from_distances": "sections", "Split": "split", "split_facets": "split", "classify": "split",
          "corner_distances": "split", "PATTERNS": "split", "Cap": "cap", "plane_edges": "cap",
          "cap_segments": "cap", "triangle_min_angles": "cap", "Cut": "cut", "CutReport": "cut",
          "CutWarning": "cut", "stair_cut": "stair", "StairCut": "stair", "StairCutError": "stair",
          "axis_plane": "stair", "Joint": "partition", "Piece": "partition", "PartitionReport": "partition",
          "Partition": "partition", "fit_rotation": "placement", "Placement": "placement",
          "place_for_printing": "placement", "flat_faces": "placement", "DIRECTIONS": "placement",
          "Plate": "plates", "Plates": "plates", "arrange": "plates", "footprint": "plates"}
_SUBMODULES = ("sections", "split", "cap", "cut", "stair", "partition", "placement", "plates")

__all__ = ["Section", "section", "slice_layers", "layer_heights", "section_from_distances", "Split", "split_facets", "classify", "corner_distances", "PATTERNS", "Cap", "plane_edges", "cap_segments", "triangle_min_angles", "Cut", "CutReport", "CutWarning", "stair_cut", "StairCut", "StairCutError", "axis_plane", "Joint", "Piece", "PartitionReport", "Partition", "fit_rotation", "Placement", "place_for_printing", "flat_faces", "DIRECTIONS", "Plate", "Plates", "arrange", "footprint"]

__getattr__, __dir__ = attach(__name__, _WHERE, globals(), submodules=_SUBMODULES)
