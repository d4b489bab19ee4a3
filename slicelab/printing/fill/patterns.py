"""Sparse infill patterns, by name: rectilinear zigzags, concentric loops, gyroid waves.

Every pattern fills polygons (the region inside the last perimeter) so that
its lines, each one line width w wide, cover the region's area at density
``w / spacing``: the line length per unit area is ``1 / spacing``. `PATTERNS`
is the one table of them (`PrintSettings.infill_pattern` names one);
`fill_pattern` calls one.

- ``rectilinear``: parallel lines `spacing` apart on a world-anchored grid,
  turned 90 degrees every other layer, linked into zigzags along the boundary
  (`slicelab.printing.fill.lines.rectilinear`).
- ``concentric``: the region's boundary and its inward offsets every
  `spacing` (GEOS buffers), closed loops.
- ``gyroid``: the section of the gyroid surface
  ``sin x cos y + sin y cos z + sin z cos x = 0`` at the layer's height: wavy
  lines whose direction turns with z, so layers interlock in 3-D. Its period is
  set so that the line length per unit area, averaged over a period of z, is
  ``1 / spacing``; a single layer is within -6 / +23 % of it. The curves are
  marching-squares contours of the function on a grid of a 32nd of the period,
  clipped to the region by GEOS.

References
----------
A. H. Schoen, "Infinite periodic minimal surfaces without self-intersections",
NASA Technical Note D-5541, 1970 (the gyroid).

See Also
--------
slicelab.printing.steps.paths.layer_paths : the patterns in a layer's print order.
"""
from __future__ import annotations

import math

import numpy as np

from ...geometry.polygons import Polygon
from ...geometry.regions import overlay, valid_region
from .lines import rectilinear

__all__ = ["PATTERNS", "fill_pattern", "concentric", "gyroid", "GYROID_LENGTH"]

#: Length of the gyroid's section lines per unit area, for a unit wave number (period 2 pi),
#: averaged over z (marching squares on 2048 x 2048 samples of three periods, 128 heights).
GYROID_LENGTH = 0.3916


def _shapely_region(polygons: list[Polygon]):
    import shapely
    return valid_region([shapely.Polygon(p.exterior, p.holes) for p in polygons if len(p.exterior) >= 3])


def _lines_of(geom) -> list[np.ndarray]:
    """The coordinates of every line part of a geometry (x, y only)."""
    import shapely
    parts = shapely.get_parts(geom)
    lines = [g for g in parts if g.geom_type in ("LineString", "LinearRing") and not g.is_empty]
    return [shapely.get_coordinates(g) for g in lines]


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
    region = _shapely_region(polygons)
    out = []
    k = 0
    while not region.is_empty:  # over the offsets, outside in
        geom = region if k == 0 else shapely.buffer(region, -k * spacing, quad_segs=8, join_style="mitre")
        if geom.is_empty:
            break
        out += _lines_of(shapely.get_rings(shapely.get_parts(geom)))
        k += 1
    return out


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
    region = _shapely_region(polygons)
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
    return [q for q in _lines_of(clipped) if len(q) >= 2]


def _rectilinear(polygons: list[Polygon], spacing: float, angle: float = 45.0, *, layer_index: int = 0,
                 z: float = 0.0) -> list[np.ndarray]:
    return rectilinear(polygons, spacing, float(angle) + 90.0 * (layer_index % 2))


#: The infill patterns by name: each takes (polygons, spacing, angle, layer_index=, z=).
PATTERNS = {"rectilinear": _rectilinear, "concentric": concentric, "gyroid": gyroid}


def fill_pattern(name: str, polygons: list[Polygon], spacing: float, angle: float = 45.0, *,
                 layer_index: int = 0, z: float = 0.0) -> list[np.ndarray]:
    """Fill polygons with a pattern of `PATTERNS`, lines `spacing` apart on average.

    Parameters
    ----------
    name : {"rectilinear", "concentric", "gyroid"}
    polygons : list of Polygon
    spacing : float
        ``line width / density`` (mm).
    angle : float, default 45
        The pattern's direction (degrees); rectilinear turns it by 90 on odd layers.
    layer_index : int
    z : float
        Height of the layer (mm), for gyroid.

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
    (['concentric', 'gyroid', 'rectilinear'], 3)
    >>> fill_pattern("honeycomb", [sq], 2.0)
    Traceback (most recent call last):
    ...
    ValueError: infill_pattern must be one of concentric, gyroid, rectilinear, got 'honeycomb'
    """
    if name not in PATTERNS:
        raise ValueError(f"infill_pattern must be one of {', '.join(sorted(PATTERNS))}, got {name!r}")
    return PATTERNS[name](polygons, spacing, angle, layer_index=layer_index, z=z)
