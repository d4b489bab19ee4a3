"""Shapely regions that are valid, and overlays that cannot fail on them.

A layer's regions come from rings that were traced round pixels, simplified
and moved onto exact offsets: two of them may touch, a ring may pinch
itself. GEOS's overlay then stops with a ``TopologyException`` ("side
location conflict") on some raster grids and not on others. `valid_region` makes
every polygon valid before uniting them (GEOS's ``make_valid``, keeping the
polygonal parts), and `overlay` runs an operation in floating point first and,
should GEOS still meet a robustness failure, again with snap-rounding on a
fine grid, which GEOS guarantees to succeed (OverlayNG with a fixed precision
model). The snapped result differs from the exact one by at most the grid's
step, far inside the pixel the rings came from.

References
----------
.. [1] M. Davis, "OverlayNG: robust overlay in JTS", 2020.
   https://lin-ear-th-inking.blogspot.com/2020/05/jts-overlayng-released.html

See Also
--------
slicelab.printing.steps.perimeters.split_by_mask : the walls cut along a mask.
"""
from __future__ import annotations

import numpy as np

__all__ = ["SNAP_GRID", "valid_region", "overlay"]

#: The grid (mm) an overlay falls back to snapping onto: a tenth of a micrometre, far below any
#: pixel or line width, far above float64's noise at the size of a build plate.
SNAP_GRID = 1e-4


def _polygonal(geoms):
    """The polygons among the parts of `geoms` (what `make_valid` leaves of a pinched ring may
    include lines and points, which have no area)."""
    import shapely
    parts = shapely.get_parts(np.asarray(geoms, dtype=object))
    while len(parts) and np.any(shapely.get_type_id(parts) >= 4):  # collections hold collections
        parts = shapely.get_parts(parts)
    return parts[shapely.get_type_id(parts) == 3] if len(parts) else parts  # 3: Polygon


def overlay(op, *geoms, grid: float = SNAP_GRID):
    """``op(*geoms)`` (a shapely set operation), retried with snap-rounding on `grid` if GEOS
    meets a robustness failure.

    Parameters
    ----------
    op : callable
        ``shapely.intersection``, ``shapely.difference``, ``shapely.union_all``...
    *geoms
        Its arguments.
    grid : float
        The snapping grid of the retry (mm).

    Examples
    --------
    >>> import shapely
    >>> a, b = shapely.box(0, 0, 2, 2), shapely.box(1, 1, 3, 3)
    >>> overlay(shapely.intersection, a, b).area
    1.0
    """
    import shapely
    try:
        return op(*geoms)
    except shapely.errors.GEOSException:
        return op(*geoms, grid_size=grid)


def valid_region(polygons):
    """One valid (multi)polygon covering shapely `polygons`, however they touch or pinch.

    Disjoint valid polygons are taken as they are (the common case costs one validity
    test); otherwise each is made valid and they are united through `overlay`.

    Examples
    --------
    >>> import shapely
    >>> bowtie = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])   # a ring that crosses itself
    >>> square = shapely.box(1.5, -1, 3, 3)
    >>> r = valid_region([bowtie, square])   # two triangles of 1 mm2, the square's 6, overlapping by 0.75
    >>> bool(r.is_valid), round(r.area, 6)
    (True, 7.25)
    """
    import shapely
    polys = _polygonal(polygons)
    if not len(polys):
        return shapely.MultiPolygon()
    shape = shapely.MultiPolygon(list(polys))
    if shapely.is_valid(shape):
        return shape
    bad = ~shapely.is_valid(polys)
    if bad.any():
        polys = np.concatenate([polys[~bad], _polygonal(shapely.make_valid(polys[bad]))])
    return overlay(shapely.union_all, polys)
