"""Gyroid infill: the section of the gyroid surface at the layer's height.

``sin x cos y + sin y cos z + sin z cos x = 0`` cut at the layer's height:
wavy lines whose direction turns with z, so layers interlock in 3-D. Its
period is set so that the line length per unit area, averaged over a period
of z, is ``1 / spacing``; a single layer is within -6 / +23 % of it. The
curves are marching-squares contours of the function on a grid of a 32nd of
the period, clipped to the region by GEOS.

References
----------
A. H. Schoen, "Infinite periodic minimal surfaces without self-intersections",
NASA Technical Note D-5541, 1970 (the gyroid).

See Also
--------
slicelab.printing.fill : the registry of patterns.
"""
from __future__ import annotations

import math

import numpy as np

from ...geometry.polygons import Polygon
from ...geometry.regions import overlay
from .pattern import Pattern, lines_of, shapely_region

__all__ = ["gyroid", "GYROID_LENGTH", "PATTERN"]

#: Length of the gyroid's section lines per unit area, for a unit wave number (period 2 pi),
#: averaged over z (marching squares on 2048 x 2048 samples of three periods, 128 heights).
GYROID_LENGTH = 0.3916


def _gyroid_values(x: np.ndarray, y: np.ndarray, z: float) -> np.ndarray:
    """sin x cos y + sin y cos z + sin z cos x on the grid of x (columns) and y (rows)."""
    return (np.sin(x)[None, :] * np.cos(y)[:, None] + np.sin(y)[:, None] * math.cos(z)
            + math.sin(z) * np.cos(x)[None, :])


def gyroid(polygons: list[Polygon], spacing: float, angle: float = 0.0, *, layer_index: int = 0,
           z: float = 0.0) -> list[np.ndarray]:
    """The gyroid's section at height `z`, clipped to the region.

    Parameters
    ----------
    polygons : list of Polygon
        The region to fill.
    spacing : float
        ``line width / density``: the line length per unit area is ``1 / spacing``
        (averaged over z).
    angle : float
        Turn of the pattern about z (degrees), the same on every layer.
    z : float
        Height of the layer (mm): the surface's section changes with it.
    layer_index : int
        Unused (the pattern table's common signature).

    Returns
    -------
    list of (k, 2) ndarray
        Open polylines (closed ones where a curve closes inside the region).

    See Also
    --------
    GYROID_LENGTH : the line length per area the period is set from.

    Examples
    --------
    >>> sq = Polygon(np.array([[0, 0], [30, 0], [30, 30], [0, 30]], float), (), 0)
    >>> lines = gyroid([sq], 2.0, z=1.0)
    >>> length = sum(np.hypot(*np.diff(q, axis=0).T).sum() for q in lines)
    >>> bool(0.9 < length * 2.0 / 900 < 1.3)
    True
    """
    import shapely

    from ...geometry.contours import march
    region = shapely_region(polygons)
    if region.is_empty:
        return []
    k = 1.0 / (spacing * GYROID_LENGTH)  # wave number: length per area = GYROID_LENGTH k = 1 / spacing
    h = 2 * math.pi / k / 32  # grid step: a 32nd of the period
    a = math.radians(angle)
    rot = np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]])  # world -> pattern frame
    corners = np.array(shapely.get_coordinates(shapely.envelope(region))) @ rot.T
    lo = np.floor(corners.min(axis=0) / h) - 2
    hi = np.ceil(corners.max(axis=0) / h) + 2
    xs, ys = np.arange(lo[0], hi[0] + 1) * h, np.arange(lo[1], hi[1] + 1) * h
    values = _gyroid_values(k * xs, k * ys, k * z)
    # A frame of positive values closes every curve along the border, outside the region.
    values[[0, -1], :] = 2.0
    values[:, [0, -1]] = 2.0
    curves = []
    for ring in march(values, 0.0):  # over curves
        xy = np.stack([xs[0] + ring[:, 1] * h, ys[0] + ring[:, 0] * h], 1) @ rot  # back to the world
        curves.append(np.vstack([xy, xy[:1]]))
    if not curves:
        return []
    clipped = shapely.line_merge(overlay(shapely.intersection, shapely.MultiLineString(curves), region))
    return [q for q in lines_of(clipped) if len(q) >= 2]


#: Its lines change with height: layers never repeat.
PATTERN = Pattern("gyroid", gyroid, "the gyroid surface's section: waves that turn with height",
                  varies_with_z=True)
