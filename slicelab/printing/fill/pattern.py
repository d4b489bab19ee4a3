"""What an infill pattern is: a function that fills a region with lines, and its properties.

Every pattern fills polygons (the region inside the last perimeter) so that
its lines, each one line width w wide, cover the region's area at density
``w / spacing``: the line length per unit area is ``1 / spacing``. A pattern
module defines one `Pattern`; `slicelab.printing.fill.PATTERNS` lists them, as
libslic3r's ``Fill::new_from_type`` does, with their properties in one place
(``FillBase::has_consistent_pattern`` there is `Pattern.varies_with_z` here).

See Also
--------
slicelab.printing.fill : the registry and `fill_pattern`.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ...geometry.polygons import Polygon

__all__ = ["Pattern", "shapely_region", "lines_of"]


@dataclass(frozen=True)
class Pattern:
    """An infill pattern.

    Attributes
    ----------
    name : str
        The name `PrintSettings.infill_pattern` gives.
    fill : callable
        ``fill(polygons, spacing, angle, *, layer_index, z) -> list of (k, 2) ndarray``: polylines
        in world coordinates whose length per unit area is ``1 / spacing``.
    help : str
        One line for ``--help`` and the documentation.
    varies_with_z : bool
        Its lines change with the layer's height (beyond the alternating direction): a layer
        cannot take the toolpaths of the layer two below it.

    Examples
    --------
    >>> from slicelab.printing.fill import PATTERNS
    >>> PATTERNS["gyroid"].varies_with_z, PATTERNS["rectilinear"].varies_with_z
    (True, False)
    """

    name: str
    fill: Callable
    help: str
    varies_with_z: bool = False


def shapely_region(polygons: list[Polygon]):
    """The polygons as one valid shapely (multi)polygon (`slicelab.geometry.regions.valid_region`)."""
    import shapely

    from ...geometry.regions import valid_region
    return valid_region([shapely.Polygon(p.exterior, p.holes) for p in polygons if len(p.exterior) >= 3])


def lines_of(geom) -> list[np.ndarray]:
    """The coordinates of every line part of a geometry (x, y only)."""
    import shapely
    parts = shapely.get_parts(geom)
    lines = [g for g in parts if g.geom_type in ("LineString", "LinearRing") and not g.is_empty]
    return [shapely.get_coordinates(g) for g in lines]
