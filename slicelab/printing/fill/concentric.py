"""Concentric infill: the region's boundary and its inward offsets every `spacing` (GEOS buffers).

See Also
--------
slicelab.printing.fill : the registry of patterns.
"""
from __future__ import annotations

import numpy as np

from ...geometry.polygons import Polygon
from .pattern import Pattern, lines_of, shapely_region

__all__ = ["concentric", "PATTERN"]


def concentric(polygons: list[Polygon], spacing: float, angle: float = 0.0, *, layer_index: int = 0,
               z: float = 0.0) -> list[np.ndarray]:
    """Closed loops: the region's boundary and its inward offsets every `spacing`.

    Parameters
    ----------
    polygons : list of Polygon
    spacing : float
        Distance between loops (mm).
    angle, layer_index, z
        Unused (the pattern table's common signature).

    Returns
    -------
    list of (k, 2) ndarray
        Closed polylines (last point equal to the first), outer loops first.

    See Also
    --------
    fill_pattern : any pattern by name.

    Examples
    --------
    >>> sq = Polygon(np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float), (), 0)
    >>> loops = concentric([sq], 2.0)
    >>> len(loops), [round(float(np.hypot(*np.diff(q, axis=0).T).sum()), 3) for q in loops]
    (3, [40.0, 24.0, 8.0])
    """
    import shapely
    region = shapely_region(polygons)
    out = []
    k = 0
    while not region.is_empty:  # over the offsets, outside in
        geom = region if k == 0 else shapely.buffer(region, -k * spacing, quad_segs=8, join_style="mitre")
        if geom.is_empty:
            break
        out += lines_of(shapely.get_rings(shapely.get_parts(geom)))
        k += 1
    return out


#: Closed loops, the same on every layer.
PATTERN = Pattern("concentric", concentric, "closed loops following the outline inward")
