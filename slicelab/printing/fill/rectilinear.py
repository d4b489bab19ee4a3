"""Rectilinear infill: parallel lines on a world-anchored grid, turned 90 degrees every other layer,
linked into zigzags along the boundary (`slicelab.printing.fill.lines.rectilinear`).

See Also
--------
slicelab.printing.fill : the registry of patterns.
"""
from __future__ import annotations

import numpy as np

from ...geometry.polygons import Polygon
from .lines import rectilinear as zigzags
from .pattern import Pattern

__all__ = ["rectilinear_pattern", "PATTERN"]


def rectilinear_pattern(polygons: list[Polygon], spacing: float, angle: float = 45.0, *, layer_index: int = 0,
                        z: float = 0.0) -> list[np.ndarray]:
    """Zigzags `spacing` apart along `angle` (degrees), turned 90 degrees on odd layers.

    Examples
    --------
    >>> sq = Polygon(np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float), (), 0)
    >>> first = [q[1] - q[0] for q in (rectilinear_pattern([sq], 2.0, 0.0, layer_index=k)[0] for k in (0, 1))]
    >>> [np.round(d / np.linalg.norm(d), 6).tolist() for d in first]   # along x, then along y
    [[1.0, 0.0], [0.0, 1.0]]
    """
    return zigzags(polygons, spacing, float(angle) + 90.0 * (layer_index % 2))


PATTERN = Pattern("rectilinear", rectilinear_pattern, "parallel lines linked into zigzags, turned 90 degrees "
                                                      "every layer")
