"""Filling: rectilinear lines, and the infill patterns by name.

`PATTERNS` is the one table of infill patterns: each module below defines one
`Pattern` (its fill function and its properties, such as whether its lines
change with height), and adding a pattern is one module and one line here.
The settings' choices (`PrintSettings.infill_pattern`), the command line's
``--infill-pattern`` and the planner's reuse of repeating layers all read it.

==========================  =====================================================
``fill.lines``              rectilinear filling lines, linked into zigzags
``fill.pattern``            what a pattern is: `Pattern`
``fill.rectilinear``        zigzags turned 90 degrees every layer
``fill.concentric``         loops following the outline inward
``fill.gyroid``             the gyroid's section: waves that turn with height
``fill.triangles``          three families of lines 60 degrees apart
==========================  =====================================================
"""
from __future__ import annotations

import numpy as np

from ...geometry.polygons import Polygon
from . import concentric, gyroid, rectilinear, triangles
from .pattern import Pattern

__all__ = ["Pattern", "PATTERNS", "fill_pattern"]

#: The infill patterns by name.
PATTERNS: dict[str, Pattern] = {p.name: p for p in (rectilinear.PATTERN, concentric.PATTERN, gyroid.PATTERN,
                                                    triangles.PATTERN)}


def fill_pattern(name: str, polygons: list[Polygon], spacing: float, angle: float = 45.0, *,
                 layer_index: int = 0, z: float = 0.0) -> list[np.ndarray]:
    """Fill polygons with a pattern of `PATTERNS`, lines `spacing` apart on average.

    Parameters
    ----------
    name : str
        A name of `PATTERNS`.
    polygons : list of Polygon
    spacing : float
        ``line width / density`` (mm).
    angle : float, default 45
        The pattern's direction (degrees); rectilinear turns it by 90 on odd layers.
    layer_index : int
    z : float
        Height of the layer (mm), for the patterns that vary with it.

    Returns
    -------
    list of (k, 2) ndarray
        Polylines in world coordinates.

    See Also
    --------
    slicelab.printing.fill.lines.line_spacing : the spacing for a density.

    Examples
    --------
    >>> sq = Polygon(np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float), (), 0)
    >>> sorted(PATTERNS), len(fill_pattern("concentric", [sq], 2.0))
    (['concentric', 'gyroid', 'rectilinear', 'triangles'], 3)
    >>> fill_pattern("honeycomb", [sq], 2.0)
    Traceback (most recent call last):
    ...
    ValueError: infill_pattern must be one of concentric, gyroid, rectilinear, triangles, got 'honeycomb'
    """
    if name not in PATTERNS:
        raise ValueError(f"infill_pattern must be one of {', '.join(sorted(PATTERNS))}, got {name!r}")
    return PATTERNS[name].fill(polygons, spacing, angle, layer_index=layer_index, z=z)
