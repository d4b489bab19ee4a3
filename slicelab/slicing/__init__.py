"""Slicing a mesh by planes: sections, splits, watertight cuts and partitions.

==========================  =====================================================
``slicing.sections``        `section`, `slice_layers` -> `Section`
``slicing.split``           `split` -> `Split` (front, rear, section), facet patterns
``slicing.cut``             `cut` -> `Cut`: two closed parts with constrained Delaunay caps
``slicing.partition``       `partition` into printable pieces, stair joints
==========================  =====================================================

The functions named like their module (`split`, `cut`, `partition`) are
reached as ``slicelab.split`` (or ``slicelab.slicing.split.split``):
``slicelab.slicing.split`` is the module.
"""
from __future__ import annotations

from .cut import (
    Cap,
    Cut,
    CutReport,
    CutWarning,
    cap_segments,
    plane_edges,
    triangle_min_angles,
    watertight_edges,
)
from .partition import (
    Joint,
    Partition,
    PartitionReport,
    Piece,
    StairCut,
    fit_rotation,
    plot_exploded,
    save_exploded_png,
    stair_cut,
)
from .sections import (
    Section,
    layer_heights,
    section,
    section_from_distances,
    slice_layers,
)
from .split import PATTERNS, Split, classify, corner_distances, split_facets

__all__ = ["Section", "section", "slice_layers", "layer_heights", "section_from_distances", "Split", "split_facets", "classify", "corner_distances", "PATTERNS", "Cap", "Cut", "CutReport", "CutWarning", "plane_edges", "cap_segments", "triangle_min_angles", "watertight_edges", "Joint", "Piece", "PartitionReport", "Partition", "stair_cut", "StairCut", "fit_rotation", "plot_exploded", "save_exploded_png"]
